// Conformal layers (issue 13, item 2): on pieces of thick spherical shells standing on spheres of
// several radii and tessellations, every layer lies at its level from the sphere (measured here
// against the exact sphere, not the mesh), the tool axis is the sphere's normal, the next layer
// lies one thickness along it, the thickness is in range, and the footprints stand on each other
// where planar layers overhang. A level that folds over along the direction is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/slicing/conformal.h"
#include "polyaxis/slicing/slice.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::slicing {
namespace {

mesh::Mesh repaired(io::RawMesh raw) { return test::repaired(std::move(raw)).mesh; }

struct Case {
  double radius, thickness, theta_deg;
  std::uint32_t n, m;  // the shell's tessellation (the sphere's is 2n around)
  double layer_mm;
};

TEST(Conformal, LayersAtEvenDistancesFromASphereAlongItsNormal) {
  for (const Case c : {Case{30, 8, 55, 64, 24, 0.6}, Case{18, 5, 40, 40, 12, 0.45}, Case{45, 6, 65, 96, 30, 0.8}}) {
    SCOPED_TRACE(c.radius);
    const Vec3 centre{0, 0, -c.radius + 20};
    // The sphere, finely tessellated so its faceting stays well under the tolerances.
    const io::RawMesh sphere_raw = test::shell_patch(centre, c.radius * 0.5, c.radius, 89, 2 * c.n, 3 * c.m);
    const mesh::Mesh region = repaired(test::shell_patch(centre, c.radius, c.radius + c.thickness, c.theta_deg, c.n, c.m));
    SliceOptions o;
    o.layer_mm = c.layer_mm, o.min_mm = 0.3, o.max_mm = 1.0;
    o.conformal_base = std::make_shared<const mesh::SurfaceDistance>(repaired(sphere_raw));
    o.conformal_edge_mm = 1.0;
    auto r = slice(region, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const auto& layers = r.value().layers;
    ASSERT_NEAR(static_cast<double>(layers.size()), c.thickness / c.layer_mm, 1.0);
    ASSERT_TRUE(r.value().conformal_base);
    // The exact sphere's faceting by the meshes, mm.
    const double tol = c.radius * (1.0 - std::cos(3.14159265358979323846 / c.n)) + 0.01;
    auto level_of = [&](Vec3 p) { return core::norm(p - centre) - c.radius; };
    for (std::size_t k = 0; k < layers.size(); ++k) {
      const Layer& l = layers[k];
      ASSERT_TRUE(l.conformal);
      const double t = l.thickness_range().first;
      EXPECT_GE(t, o.min_mm);
      EXPECT_LE(t, o.max_mm);
      EXPECT_NEAR(l.conformal->level_mm, (static_cast<double>(k) + 0.5) * t, 1e-6 + tol);
      for (const auto& ring : l.conformal->contours) {
        for (const Vec3& p : ring) EXPECT_NEAR(level_of(p), l.conformal->level_mm, tol);
      }
      // Points of the section lifted onto the surface: at the level, the axis the sphere's
      // normal, and one thickness down that axis the previous layer's level.
      const auto c0 = geom2d::centroid(l.polygons);
      const double step = 1.5;
      for (double du = -9; du <= 9; du += step) {
        const Vec3 p = l.frame.to_world(c0.x + du, c0.y + du / 2);
        const auto lifted = lift(*o.conformal_base, l, p);
        ASSERT_TRUE(lifted);
        EXPECT_NEAR(level_of(lifted->point), l.conformal->level_mm, tol);
        // The gradient of the distance to a facet is its normal: within a facet's turn (the
        // sphere's 2n segments) of the exact normal.
        EXPECT_GT(core::dot(lifted->axis, core::normalized(lifted->point - centre)), std::cos(3.14159265358979323846 / c.n));
        EXPECT_NEAR(level_of(lifted->point - lifted->axis * t), l.conformal->level_mm - t, tol);
      }
    }
    // Σ area × thickness, the areas on the curved surfaces, is the shell's volume (to its faceting).
    const double kPi = 3.14159265358979323846, r1 = c.radius + c.thickness;
    const double volume = 2.0 * kPi / 3.0 * (r1 * r1 * r1 - c.radius * c.radius * c.radius) * (1.0 - std::cos(c.theta_deg * kPi / 180.0));
    EXPECT_NEAR(r.value().volume_estimate_mm3, volume, 0.03 * volume);
    // The radial rim stands on the layer below along the normal; parallel planes overhang there.
    EXPECT_LT(overhang_estimate_mm2(r.value(), 30.0, 0.0), 0.5);
    SliceOptions planar;
    planar.layer_mm = c.layer_mm;
    auto p = slice(region, planar);
    ASSERT_TRUE(p.ok());
    EXPECT_GT(overhang_estimate_mm2(p.value(), 30.0, 0.0), 10.0);
  }
}

TEST(Conformal, ALevelThatFoldsOverAlongTheDirectionIsRefused) {
  const Vec3 centre{0, 0, 0};
  const mesh::Mesh region = repaired(test::shell_patch(centre, 20, 25, 50, 48, 12));
  SliceOptions o;
  o.direction = {1, 0, 0};  // the spherical levels fold over seen along X
  o.layer_mm = 0.5, o.min_mm = 0.3, o.max_mm = 1.0;
  o.conformal_base = std::make_shared<const mesh::SurfaceDistance>(repaired(test::shell_patch(centre, 10, 20, 89, 96, 36)));
  auto r = slice(region, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
  EXPECT_NE(r.error().message.find("no height field"), std::string::npos) << r.error().message;
}

TEST(Conformal, ARegionOffTheBaseIsRefused) {
  const mesh::Mesh region = repaired(test::box({0, 0, 5}, {10, 10, 9}));
  SliceOptions o;
  o.layer_mm = 0.5, o.min_mm = 0.3, o.max_mm = 1.0;
  o.conformal_base = std::make_shared<const mesh::SurfaceDistance>(repaired(test::box({-5, -5, -3}, {15, 15, 0})));
  auto r = slice(region, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
  // Resting on it, the levels of a box on a flat base are its planar layers.
  o.conformal_base = std::make_shared<const mesh::SurfaceDistance>(repaired(test::box({-5, -5, -3}, {15, 15, 5})));
  r = slice(region, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r.value().layers.size(), 8u);
  for (const Layer& l : r.value().layers) {
    EXPECT_NEAR(l.conformal->low_mm, l.conformal->high_mm, 1e-6);
    EXPECT_NEAR(l.area_mm2, 100.0, 1e-3);
  }
}

}  // namespace
}  // namespace polyaxis::slicing
