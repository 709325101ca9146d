// The screening of a split (split_screen.h): a cut that would leave a piece thinner on average than
// a region can be laid is not a split, before any exact cut is paid for.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tuple>

#include "analysis/region_geometry.h"
#include "analysis/split_screen.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::analysis::detail {
namespace {

Screened screen(const mesh::RepairedMesh& part, double plane_z, double min_thickness_mm) {
  const HostFaces faces = host_faces(part.mesh, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, 30.0);
  HostRegion host{&part.mesh, &part.topology, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, false, {}, &faces, min_thickness_mm};
  std::vector<std::uint32_t> seeds;  // the facets of the top face
  for (std::uint32_t f = 0; f < part.mesh.triangles.size(); ++f) {
    if (part.mesh.corner(f, 0).z > 9.99 && part.mesh.corner(f, 1).z > 9.99 && part.mesh.corner(f, 2).z > 9.99) seeds.push_back(f);
  }
  const Vec3 starts[] = {{0, 0, 1}};
  return screen_split(host, {0, 0, plane_z}, {0, 0, 1}, seeds, starts, 30.0);
}

// A 20 x 10 x 10 box cut across z: the slab above the plane is the child.
TEST(ScreenSplit, ASliverThinnerThanTheLeastRegionIsNoSplitAndAThickSlabIs) {
  const auto part = polyaxis::test::repaired(polyaxis::test::box({0, 0, 0}, {20, 10, 10}));
  for (const double min_t : {0.3, 1.0}) {
    EXPECT_FALSE(screen(part, 10.0 - 0.2 * min_t, min_t).valid) << "a child 0.2 of the least thickness";
    EXPECT_FALSE(screen(part, 0.2 * min_t, min_t).valid) << "a parent 0.2 of the least thickness";
    EXPECT_TRUE(screen(part, 10.0 - 3.0 * min_t, min_t).valid) << "a child 3 times the least thickness";
    EXPECT_TRUE(screen(part, 3.0 * min_t, min_t).valid) << "a parent 3 times the least thickness";
  }
  EXPECT_TRUE(screen(part, 9.9, 0.0).valid) << "without a least thickness any slab is a split";
}

}  // namespace
}  // namespace polyaxis::analysis::detail

namespace polyaxis::analysis::detail {
namespace {

// Some of the solid this close below a lowest corner holds it: the least thickness of a region.
constexpr double kProbeMm = 0.3;

// A prism 20 long lying along y with a keel pointing down: its two lower faces are steep (17° from
// vertical), so no facet overhangs at 30°, yet its first layer along +Z starts on nothing.
io::RawMesh keel_prism(double half_width, double depth, double length) {
  io::RawMesh m;
  for (const double y : {0.0, length}) {
    m.points.push_back({-half_width, y, depth});
    m.points.push_back({half_width, y, depth});
    m.points.push_back({0, y, 0});
  }
  m.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  return m;
}

// A tube (od 40, bore 34, 48 sides, 50 tall) cut by the plane x = C towards +X. Just past the
// bore (the corners at 17 mm) the parent keeps a film of the wall under the child's first layer.
TEST(UndersideInCut, AFilmTheCutLeavesOverATubesBoreIsTheChildsUndersideAndASolidWallIsNot) {
  const auto tube = polyaxis::test::repaired(polyaxis::test::revolve({{20.0, 0.0}, {20.0, 50.0}}, 48, 17.0));
  const double film = underside_in_cut_mm2(tube.mesh, {17.1, 0, 0}, {1, 0, 0}, 0.3);
  // The two facet columns either side of x = 17 (corners at 17 and 17·cos 7.5° = 16.85 mm), 50 mm
  // tall and 2.22 mm wide, seen along X.
  const double column = 2.0 * 17.0 * std::sin(3.75 * std::numbers::pi / 180.0) * 50.0 * std::cos(3.75 * std::numbers::pi / 180.0);
  EXPECT_NEAR(film, 2.0 * column, 1e-6);
  EXPECT_EQ(underside_in_cut_mm2(tube.mesh, {17.1, 0, 0}, {1, 0, 0}, 0.0), 0.0) << "no least layer: only faces in the cut count";
  EXPECT_EQ(underside_in_cut_mm2(tube.mesh, {18.0, 0, 0}, {1, 0, 0}, 0.3), 0.0) << "a wall over 0.3 mm thick under the cut";
}

// An L (a 20 x 10 x 10 block with a 10 x 10 ledge from z = 5 to 10 on its side) cut across z: a
// plane 0.1 mm above the ledge's underside leaves the parent a film of the ledge, parallel to it.
TEST(UndersideInCut, AFilmParallelToTheCutCountsWholeAndALedgeThickerThanALayerDoesNot) {
  const auto l = polyaxis::test::repaired(polyaxis::test::prism_xz({{0, 0}, {20, 0}, {20, 5}, {30, 5}, {30, 10}, {0, 10}}, 10.0));
  EXPECT_NEAR(underside_in_cut_mm2(l.mesh, {0, 0, 5.1}, {0, 0, 1}, 0.3), 100.0, 1e-6);
  EXPECT_EQ(underside_in_cut_mm2(l.mesh, {0, 0, 5.5}, {0, 0, 1}, 0.3), 0.0);
  EXPECT_EQ(underside_in_cut_mm2(l.mesh, {0, 0, 5.1}, {0, 0, 1}, 0.0), 0.0) << "no least layer: only faces in the cut count";
  EXPECT_NEAR(underside_in_cut_mm2(l.mesh, {0, 0, 5.0 + 1e-3}, {0, 0, 1}, 0.0), 100.0, 1e-6) << "the ledge's underside in the cut";
}

TEST(MidAirStarts, AKeelStartsOnNothingAtOneCornerWhereverItLeans) {
  for (const auto& [half_width, depth, length] : {std::tuple{3.0, 10.0, 20.0}, std::tuple{1.0, 6.0, 7.5}}) {
    const auto prism = polyaxis::test::repaired(keel_prism(half_width, depth, length));
    const Vec3 wall{-50, 0, 0}, wall_normal{1, 0, 0};  // a base plane no corner lies on
    ASSERT_EQ(unsupported(prism.mesh, {0, 0, 1}, 30.0, wall, wall_normal), 0.0);
    // Level: the keel is one line of lowest corners, counted once.
    EXPECT_EQ(mid_air_starts(prism.mesh, {0, 0, 1}, wall, wall_normal, kProbeMm).size(), 1u);
    // Leaning along the keel: its lower end.
    for (const double lean : {0.2, -0.3}) {
      const auto starts = mid_air_starts(prism.mesh, core::normalized(Vec3{0, lean, 1}), wall, wall_normal, kProbeMm);
      ASSERT_EQ(starts.size(), 1u) << lean;
      EXPECT_NEAR(starts[0].y, lean > 0 ? 0.0 : length, 1e-12) << lean;
      EXPECT_NEAR(starts[0].z, 0.0, 1e-12) << lean;
    }
    // Grown from a base through the keel: nothing starts in mid-air.
    EXPECT_TRUE(mid_air_starts(prism.mesh, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, kProbeMm).empty());
  }
}

TEST(MidAirStarts, ABlockOnItsBaseAndAPocketsFloorStartNowhere) {
  const auto block = polyaxis::test::repaired(polyaxis::test::box({0, 0, 0}, {20, 10, 10}));
  EXPECT_TRUE(mid_air_starts(block.mesh, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, kProbeMm).empty());
  EXPECT_TRUE(mid_air_starts(block.mesh, core::normalized(Vec3{0.3, -0.2, 1}), {0, 0, 0}, {0, 0, 1}, kProbeMm).empty());
  // Along -Z from the top face, the block's underside is one flat face down: one start.
  EXPECT_EQ(mid_air_starts(block.mesh, {0, 0, 1}, {0, 0, 10}, {0, 0, -1}, kProbeMm).size(), 1u);
  // A torus on its side built up from a plane through its lowest ring: the hole's floor and the
  // inner ring are no starts (the solid is below or beside them).
  const auto ring = polyaxis::test::repaired(polyaxis::test::torus(20, 5, 48, 24));
  EXPECT_TRUE(mid_air_starts(ring.mesh, {0, 0, 1}, {0, 0, -5}, {0, 0, 1}, kProbeMm).empty());
}

}  // namespace
}  // namespace polyaxis::analysis::detail
