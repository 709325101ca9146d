// Conformal layers (issue 13, item 2): on pieces of thick spherical shells standing on spheres of
// several radii and tessellations, every layer lies at its level from the sphere (measured here
// against the exact sphere, not the mesh), the tool axis is the sphere's normal, the next layer
// lies one thickness along it, the thickness is in range, and the footprints stand on each other
// where planar layers overhang. A level that folds over along the direction is refused.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/slicing/conformal.h"
#include "polyaxis/slicing/section.h"
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

// A level that meets the surface at a grazing angle: the top of a box over a sphere, where the
// distance from the sphere grows slowly along the face (its gradient along the face is 0.13–0.28
// at these levels). A crossing interpolated linearly between an edge's ends
// lands up to e / 0.17 off the level set for a field e mm off linear: the tb100k branch's end
// face carried a 0.1–0.2 mm sawtooth that way, and the paths offset from its notches left a bare
// strip under the next layer. Each crossing is now on the field's level.
TEST(Conformal, ContoursLieOnTheLevelWhereItMeetsTheSurfaceAtAGrazingAngle) {
  for (const double radius : {30.0, 18.0}) {
    for (const double edge : {1.0, 2.5}) {
      SCOPED_TRACE(fmt::format("sphere r {}, edges {} mm", radius, edge));
      const Vec3 centre{0, 0, -radius};
      const mesh::SurfaceDistance base(repaired(test::shell_patch(centre, radius * 0.5, radius, 89, 96, 36)));
      const mesh::Mesh box = repaired(test::box({-10, -9, 0}, {9, 10, 4}));
      const std::optional<mesh::Mesh> fine = refined_for_levels(box, base, edge);
      ASSERT_TRUE(fine);
      std::vector<double> field(fine->vertices.size());
      for (std::size_t i = 0; i < field.size(); ++i) field[i] = base.nearest(fine->vertices[i]).signed_mm;
      SectionContext linear(*fine, {0, 0, 1}, field), exact(*fine, {0, 0, 1}, field);
      exact.set_field_at([&base](Vec3 p) { return base.nearest(p).signed_mm; });
      const Frame plane = plane_frame({0, 0, 1}, 0.0);
      std::vector<std::uint32_t> all(fine->triangles.size());
      for (std::uint32_t f = 0; f < all.size(); ++f) all[f] = f;
      SectionScratch scratch;
      for (const double above_top : {0.3, 0.6, 0.9}) {
        const double level = base.nearest({0, 0, 4}).signed_mm + above_top;
        // The largest miss of the level by a section's corners on the box's top face.
        auto worst = [&](const SectionContext& ctx, int& on_top) {
          double miss = 0.0;
          on_top = 0;
          for (const geom2d::Ring& ring : geom2d::rings_of(section(ctx, level, plane, all, scratch).polygons)) {
            for (const geom2d::Point& q : ring) {
              const Vec3 p = plane.to_world(geom2d::to_mm(q.x), geom2d::to_mm(q.y)) + Vec3{0, 0, 4};
              if (std::fabs(p.x) > 8.8 || std::fabs(p.y) > 8.8) continue;  // on the box's sides
              miss = std::max(miss, std::fabs(base.nearest(p).signed_mm - level)), ++on_top;
            }
          }
          return miss;
        };
        int n_exact = 0, n_linear = 0;
        const double exact_miss = worst(exact, n_exact), linear_miss = worst(linear, n_linear);
        ASSERT_GE(n_exact, 4);
        EXPECT_EQ(n_exact, n_linear);  // the same edges are crossed: only where along them moves
        EXPECT_LT(exact_miss, 1e-4) << "level " << level;
        // What the linear crossing missed by, and what this test would see without the fix.
        EXPECT_GT(linear_miss, 10.0 * exact_miss + 1e-4) << "level " << level;
      }
    }
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
