// mesh::tube: the solid swept along a polyline, closed and outward, its volume the swept balls'.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/self_intersections.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/mesh/tube.h"

namespace polyaxis::mesh {
namespace {

using core::Vec3;
constexpr double kPi = std::numbers::pi;

void expect_solid(const Mesh& m) {
  const EdgeTopology t = build_topology(m);
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.misoriented_edges, 0u);
  EXPECT_GT(signed_volume(m), 0.0);
  EXPECT_TRUE(self_intersecting_faces(m).empty());
}

// The volume of a polygonal tube of SIDES faces and radius R (its rings' corners on the circle):
// the prism's section is the regular polygon's area.
double polygon_area(double r, int sides) { return 0.5 * sides * r * r * std::sin(2.0 * kPi / sides); }

TEST(Tube, AStraightTubeIsAPrismWithRoundEnds) {
  for (const int sides : {8, 32, 61}) {
    for (const Vec3 dir : {Vec3{0, 0, 1}, core::normalized(Vec3{0.6, -0.48, 0.64}), Vec3{1, 0, 0}}) {
      const double r = 2.5, length = 40.0;
      std::vector<Vec3> axis;
      for (int i = 0; i <= 20; ++i) axis.push_back(Vec3{3, -1, 7} + dir * (length * i / 20.0));
      const Mesh m = tube(axis, std::vector<double>(axis.size(), r), sides, 6);
      expect_solid(m);
      // The prism plus the two end caps (a polygonal hemisphere each: less than a ball in all, more
      // than the cone-like hull of its rings).
      const double prism = polygon_area(r, sides) * length, ball = 4.0 / 3.0 * kPi * r * r * r;
      EXPECT_GT(signed_volume(m), prism + 0.6 * ball) << sides;
      EXPECT_LT(signed_volume(m), prism + ball) << sides;
      // Every corner lies on the capsule: R from the axis segment.
      for (const Vec3& v : m.vertices) {
        const double u = std::clamp(core::dot(v - axis.front(), dir) / length, 0.0, 1.0);
        EXPECT_NEAR(core::norm(v - (axis.front() + dir * (u * length))), r, 1e-9);
      }
    }
  }
}

TEST(Tube, ABentTubeOfChangingRadiusHoldsItsAxisAndCrossesNothing) {
  // A quarter turn of radius 30 mm, the tube's radius from 3 to 5 mm along it.
  std::vector<Vec3> axis;
  std::vector<double> radii;
  for (int i = 0; i <= 45; ++i) {
    const double a = 0.5 * kPi * i / 45.0;
    axis.push_back({30.0 - 30.0 * std::cos(a), 0.0, 30.0 * std::sin(a)});
    radii.push_back(3.0 + 2.0 * i / 45.0);
  }
  const Mesh m = tube(axis, radii, 24, 4);
  expect_solid(m);
  // The swept volume: Pappus, the mean section along the arc (the polygon's, to its faceting).
  double swept = 0.0;
  for (int i = 0; i < 45; ++i) swept += polygon_area(0.5 * (radii[i] + radii[i + 1]), 24) * 30.0 * 0.5 * kPi / 45.0;
  EXPECT_NEAR(signed_volume(m), swept + 2.0 / 3.0 * kPi * (27.0 + 125.0), 0.03 * swept);
  // An axis that comes back nearer than the tube is thick (a U 10 mm wide, the tube 12 mm) folds
  // the tube over itself: the caller's check sees it; 8 mm thick, it does not.
  const std::vector<Vec3> u_turn{{0, 0, 0}, {0, 0, 10}, {10, 0, 10.5}, {10, 0, 0}};
  EXPECT_FALSE(self_intersecting_faces(tube(u_turn, std::vector<double>(4, 6.0), 16, 3)).empty());
  EXPECT_TRUE(self_intersecting_faces(tube(u_turn, std::vector<double>(4, 4.0), 16, 3)).empty());
}

}  // namespace
}  // namespace polyaxis::mesh
