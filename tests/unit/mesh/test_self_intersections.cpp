// The grid search for self-intersections (parallel, mesh/self_intersections.cpp) against CGAL's
// box_intersection_d over the same exact predicates, on intersecting and clean parts of several
// sizes, tessellations and orientations, and on a part uneven enough for the fallback.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/self_intersections.h"
#include "support/meshes.h"

namespace polyaxis::mesh {
namespace {

// RAW turned by DEG about the axis (1, 1, 0)/√2 and moved by SHIFT.
io::RawMesh turned(io::RawMesh raw, double deg, core::Vec3 shift) {
  const double a = deg * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
  const core::Vec3 k = core::normalized(core::Vec3{1, 1, 0});
  for (auto& p : raw.points) {
    const core::Vec3 v{p.x, p.y, p.z};
    const core::Vec3 r = v * c + core::cross(k, v) * s + k * (core::dot(k, v) * (1.0 - c)) + shift;
    p = {static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.z)};
  }
  return raw;
}

Mesh mesh_of(const io::RawMesh& raw) {
  RepairOptions o;
  o.check_self_intersections = false;
  auto r = repair(raw, o);
  EXPECT_TRUE(r.ok()) << r.error().message;
  return r.value().mesh;
}

TEST(SelfIntersections, GridFindsWhatTheBoxIntersectionFinds) {
  struct Case {
    const char* name;
    io::RawMesh raw;
    bool intersects;
  };
  const std::vector<Case> cases = {
      {"clean torus", test::torus(20, 5, 60, 24), false},
      {"two tori", test::join(test::torus(20, 5, 60, 24), turned(test::torus(18, 4, 47, 19), 37.0, {9, -4, 3})), true},
      {"cube and box", test::join(test::cube(), turned(test::box({5, 5, 5}, {15, 15, 15}), 11.0, {0, 0, 0})), true},
      {"touching cubes", test::join(test::cube(), test::box({10, 0, 0}, {20, 10, 10})), true},
      {"fine torus through a coarse slab", test::join(test::torus(30, 6, 120, 40), turned(test::box({-50, -50, -1}, {50, 50, 1}), 23.0, {1, 2, 0})), true},
      {"frustum and bar", test::join(test::frustum(15, 8, 30, 48), turned(test::bent_bar(25, 4, 120, 40, 16), 5.0, {-20, 3, 10})), true},
      {"far apart", test::join(test::torus(20, 5, 40, 20), turned(test::cube(), 0.0, {100, 0, 0})), false},
  };
  for (const Case& c : cases) {
    const Mesh m = mesh_of(c.raw);
    const auto grid = self_intersecting_faces(m);
    const auto boxes = detail::self_intersecting_faces_by_boxes(m);
    EXPECT_EQ(grid, boxes) << c.name;
    EXPECT_EQ(!grid.empty(), c.intersects) << c.name << ": " << grid.size();
  }
}

}  // namespace
}  // namespace polyaxis::mesh
