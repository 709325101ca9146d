// Point-to-surface distance (the base of conformal layers) and edge refinement.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::mesh {
namespace {

Mesh repaired(io::RawMesh raw) { return test::repaired(std::move(raw)).mesh; }

// Uniform numbers in [0, 1) from a seed (a 64-bit LCG: the same sequence everywhere).
struct Uniform {
  std::uint64_t state;
  explicit Uniform(std::uint64_t seed) : state(seed) {}
  double operator()() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  }
};

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

// The sign holds wherever the nearest point lies, on a face, an edge or a vertex (the faces' own
// normals get it wrong beyond a rim: a point level with a flat top, off its edge).
TEST(SurfaceDistance, SignAgreesWithTheWindingNumberAroundEdgesAndVertices) {
  for (const auto& raw : {test::frustum(28, 50, 75, 16), test::box({0, 0, 0}, {10, 20, 10}), test::spherical_cap(20, 8, 12, 4)}) {
    const Mesh m = repaired(raw);
    const SurfaceDistance d(m);
    Uniform next(12345);
    int wrong = 0, n = 0;
    for (int i = 0; i < 3000; ++i) {
      Vec3 p{-80 + 160 * next(), -80 + 160 * next(), -20 + 120 * next()};
      if (i % 3 == 0) p.z = 75.0;  // level with the frustum's top, the box's and cap's beyond
      if (i % 3 == 1) p.z = 10.0;
      const double w = winding_number(m, p);
      if (std::abs(w) > 0.01 && std::abs(w - 1.0) > 0.01) continue;  // on the surface
      const Nearest q = d.nearest(p);
      if (std::abs(q.signed_mm) < 1e-6) continue;
      ++n;
      if ((q.signed_mm < 0.0) != (w > 0.5)) ++wrong;
    }
    EXPECT_GT(n, 2000);
    EXPECT_EQ(wrong, 0);
  }
}

// A search started from the answer for a nearby point (a walk along a path, the steps of an
// iteration) finds the same nearest point and signed distance as one from scratch, however far the
// hint's point lies, on long thin triangles (a frustum's sides) as on a box and a cap.
TEST(SurfaceDistance, ASearchFromANearbyAnswerFindsTheSame) {
  for (const auto& raw : {test::frustum(28, 50, 75, 128), test::box({0, 0, 0}, {10, 20, 10}), test::spherical_cap(20, 8, 12, 4)}) {
    const Mesh m = repaired(raw);
    const SurfaceDistance d(m);
    Uniform next(777);
    Nearest before = d.nearest({0, 0, 0});
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p{-70 + 140 * next(), -70 + 140 * next(), -20 + 110 * next()};
      const Nearest fresh = d.nearest(p), hinted = d.nearest(p, before);
      EXPECT_NEAR(hinted.signed_mm, fresh.signed_mm, 1e-9) << i;
      EXPECT_NEAR(core::norm(hinted.point - fresh.point), 0.0, 1e-9) << i;
      EXPECT_GT(core::dot(hinted.normal, fresh.normal), 1.0 - 1e-9) << i;
      before = i % 2 == 0 ? hinted : d.nearest(p + Vec3{0.3, -0.2, 0.1});  // the next query is far from it, or near
    }
  }
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

TEST(Refine, ByAPredicateWithinAFaceBudget) {
  const Mesh m = repaired(test::box({0, 0, 0}, {40, 10, 10}));
  // Only edges crossing x = 20.5 are cut, down to 1 mm.
  auto crossing = [](Vec3 a, Vec3 b) { return core::norm(b - a) > 1.0 && (a.x - 20.5) * (b.x - 20.5) < 0.0; };
  const auto fine = refine(m, crossing, 100000);
  ASSERT_TRUE(fine);
  EXPECT_TRUE(build_topology(*fine).closed());
  EXPECT_NEAR(signed_volume(*fine), 4000.0, 1e-6);
  for (std::size_t f = 0; f < fine->triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = fine->corner(f, k), b = fine->corner(f, (k + 1) % 3);
      EXPECT_FALSE(crossing(a, b));
    }
  }
  EXPECT_FALSE(refine(m, crossing, 20));  // more faces than that
}

}  // namespace
}  // namespace polyaxis::mesh
