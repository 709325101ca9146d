// Point-to-surface distance (the base of conformal layers) and edge refinement.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"

namespace polyaxis::mesh {
namespace {

Mesh repaired(io::RawMesh raw) {
  auto r = repair(std::move(raw));
  EXPECT_TRUE(r.ok());
  return r.value().mesh;
}

TEST(SurfaceDistance, SignedDistanceAndNearestPointOfABox) {
  const Mesh box = repaired(test::box({0, 0, 0}, {10, 20, 10}));
  const SurfaceDistance d(box);
  ASSERT_FALSE(d.empty());
  const Nearest above = d.nearest({5, 7, 13});
  EXPECT_NEAR(above.signed_mm, 3.0, 1e-9);
  EXPECT_NEAR(core::norm(above.point - Vec3{5, 7, 10}), 0.0, 1e-9);
  EXPECT_NEAR(above.normal.z, 1.0, 1e-12);
  const Nearest inside = d.nearest({5, 7, 4});
  EXPECT_NEAR(inside.signed_mm, -4.0, 1e-9);  // behind the nearest face (the bottom, 4 mm under)
  const Nearest corner = d.nearest({13, 24, 10});
  EXPECT_NEAR(corner.signed_mm, 5.0, 1e-9);  // to the edge x = 10, y = 20
  const SurfaceDistance none(Mesh{});
  EXPECT_TRUE(none.empty());
}

TEST(Refine, EveryEdgeShortClosedOrientedVolumeKept) {
  for (const double limit : {0.7, 2.5}) {
    for (const auto& raw : {test::box({0, 0, 0}, {10, 3, 7}), test::cylinder({1, 2, 3}, {0.2, 0.1, 1}, 4, 15, 12), test::spherical_cap(20, 8, 24, 6)}) {
      const Mesh m = repaired(raw);
      const Mesh fine = refine(m, limit);
      EXPECT_GT(fine.triangles.size(), m.triangles.size());
      double longest = 0.0;
      for (std::size_t f = 0; f < fine.triangles.size(); ++f) {
        for (int k = 0; k < 3; ++k) longest = std::max(longest, core::norm(fine.corner(f, (k + 1) % 3) - fine.corner(f, k)));
      }
      EXPECT_LE(longest, limit + 1e-12);
      const EdgeTopology t = build_topology(fine);
      EXPECT_TRUE(t.closed());
      EXPECT_EQ(t.misoriented_edges, 0u);
      EXPECT_NEAR(signed_volume(fine), signed_volume(m), 1e-9 * std::abs(signed_volume(m)));
      EXPECT_NEAR(surface_area(fine), surface_area(m), 1e-9 * surface_area(m));
    }
  }
}

}  // namespace
}  // namespace polyaxis::mesh
