// The full pipeline on parts the test builds (other sizes, angles and numbers of branches than the
// reference parts), with the same checks: region count, directions within 5°, volumes summing to
// the part, support-free regions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "decompose_checks.h"
#include "support/mesh_union.h"
#include "support/meshes.h"

namespace polyaxis::analysis::test {
namespace {

using io::RawMesh;

RawMesh transformed(RawMesh m, const std::function<Vec3(Vec3)>& f) {
  for (Vec3& p : m.points) p = f(p);
  return m;
}

// Rotation by DEG about the axis through the origin along Y (x towards −z for positive DEG is
// OpenSCAD's rotate([0, DEG, 0])) or Z.
Vec3 rotate_y(Vec3 p, double deg) {
  const double c = std::cos(deg * kTestPi / 180.0), s = std::sin(deg * kTestPi / 180.0);
  return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
}
Vec3 rotate_z(Vec3 p, double deg) {
  const double c = std::cos(deg * kTestPi / 180.0), s = std::sin(deg * kTestPi / 180.0);
  return {c * p.x - s * p.y, s * p.x + c * p.y, p.z};
}

// A prism of N sides around Z (radius R to its corners), z in [z0, z1], outward.
RawMesh prism_z(double r, std::uint32_t n, double z0, double z1) {
  RawMesh m;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double a = 2.0 * kTestPi * i / n;
    m.points.push_back({r * std::cos(a), r * std::sin(a), z0});
    m.points.push_back({r * std::cos(a), r * std::sin(a), z1});
  }
  const auto bottom = static_cast<std::uint32_t>(m.points.size());
  m.points.push_back({0, 0, z0});
  m.points.push_back({0, 0, z1});
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({2 * i, 2 * j, 2 * j + 1});
    m.triangles.push_back({2 * i, 2 * j + 1, 2 * i + 1});
    m.triangles.push_back({bottom, 2 * j, 2 * i});
    m.triangles.push_back({bottom + 1, 2 * i + 1, 2 * j + 1});
  }
  return m;
}

TEST(DecomposeGenerated, LBlockWithAnotherArm) {
  // Column 16 x 16 x 50; arm 56 long, 16 high at the top, reaching +X.
  const auto part = repaired(polyaxis::test::mesh_union(polyaxis::test::box({0, 0, 0}, {16, 16, 50}),
                                                        polyaxis::test::box({0, 0, 34}, {56, 16, 50})));
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 2u);
  expect_partition(tree, part.mesh);
  const auto ids = match_directions(tree, {{0, 0, 1}, {1, 0, 0}});
  EXPECT_EQ(ids[0], 0);
  EXPECT_NEAR(tree.regions[0].volume_mm3, 16.0 * 16.0 * 50.0, 13.0);
  EXPECT_NEAR(tree.regions[1].volume_mm3, 40.0 * 16.0 * 16.0, 11.0);
  expect_support_free(tree);
}

// With the machine's tilt reach given, every region's direction stays within it of the root's: the
// arm (90° wanted) goes to the rim of a 75° reach and is still support-free; within 60° nothing
// holds it and the part is left unsplit rather than given a direction out of reach.
TEST(DecomposeGenerated, DirectionsStayWithinTheReach) {
  const auto part = repaired(polyaxis::test::mesh_union(polyaxis::test::box({0, 0, 0}, {16, 16, 50}),
                                                        polyaxis::test::box({0, 0, 34}, {56, 16, 50})));
  CentroidalAxisOptions ao;
  ao.start_direction = {0, 0, 1};
  auto axis = centroidal_axis(part.mesh, part.topology, ao);
  ASSERT_TRUE(axis.ok());
  for (const double reach : {80.0, 75.0, 60.0}) {
    SCOPED_TRACE(reach);
    DecomposeOptions dopt;
    dopt.reach_deg = reach;
    auto tree = decompose(part.mesh, axis.value(), dopt);
    ASSERT_TRUE(tree.ok());
    expect_partition(tree.value(), part.mesh);
    for (const Region& r : tree.value().regions) EXPECT_LE(angle_between_deg(r.build_direction, {0, 0, 1}), reach + 1e-6) << r.id;
    if (reach > 60.0) {
      ASSERT_EQ(tree.value().regions.size(), 2u);
      expect_support_free(tree.value());
    } else {
      EXPECT_EQ(tree.value().regions.size(), 1u);
    }
  }
}

// With the head against the plate given (DecomposeOptions::least_height_mm), no child reaches
// below the height at which the head can lay it. The head here is the default machine's: a
// cylinder of radius 25 mm from 20 mm up its axis, the axis at most 60° from the layer's normal,
// 0.5 mm above the plate. Without the rule the candelabra's column is cut lengthwise and a half
// built downwards from the top (118° from the root) down to the foot, where that head cannot reach.
TEST(DecomposeGenerated, NoChildReachesBelowWhereTheHeadCanLayItOverThePlate) {
  auto read = io::read_part(std::string(POLYAXIS_CORPUS_DIR) + "/branches/candelabra.stl");
  ASSERT_TRUE(read.ok());
  const auto part = repaired(std::move(read.value().mesh));
  CentroidalAxisOptions ao;
  ao.start_direction = {0, 0, 1};
  auto axis = centroidal_axis(part.mesh, part.topology, ao);
  ASSERT_TRUE(axis.ok());
  auto least_height = [](double tilt_rad) {
    const double t = std::max(0.0, tilt_rad - 60.0 * kTestPi / 180.0);
    return std::max(0.0, 0.5 - (20.0 * std::cos(t) - 25.0 * std::sin(t)));
  };
  // The lowest child's shortfall: how far below the height its direction needs it reaches.
  auto shortfall = [&](const RegionTree& tree) {
    double worst = 0.0;
    for (const Region& r : tree.regions) {
      if (!r.parent) continue;
      const double need = least_height(angle_between_deg(r.build_direction, {0, 0, 1}) * kTestPi / 180.0);
      for (const Vec3& v : r.mesh.vertices) worst = std::max(worst, need - v.z);
    }
    return worst;
  };
  for (const bool with_head : {false, true}) {
    SCOPED_TRACE(with_head);
    DecomposeOptions dopt;
    dopt.reach_deg = 120.0;
    if (with_head) dopt.least_height_mm = least_height;
    auto tree = decompose(part.mesh, axis.value(), dopt);
    ASSERT_TRUE(tree.ok());
    expect_partition(tree.value(), part.mesh);
    if (with_head) {
      EXPECT_LE(shortfall(tree.value()), 1e-3);
    } else {
      EXPECT_GT(shortfall(tree.value()), 5.0);
    }
  }
}

class LeaningBar : public ::testing::TestWithParam<double> {};

TEST_P(LeaningBar, BuildsAlongItsIncline) {
  const double lean = GetParam();
  const double s = std::sin(lean * kTestPi / 180.0);
  // A 10 x 16 x 50 bar leaning LEAN degrees towards +X, its bottom end inside a 70 x 30 x 10 plate
  // (the end's upper edge at z = 8).
  const RawMesh bar = transformed(polyaxis::test::box({0, 0, 0}, {10, 16, 50}),
                                  [&](Vec3 p) { return rotate_y(p, lean) + Vec3{12, 7, 8}; });
  const auto part = repaired(polyaxis::test::mesh_union(polyaxis::test::box({0, 0, 0}, {70, 30, 10}), bar));
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 2u);
  expect_partition(tree, part.mesh);
  const auto ids = match_directions(tree, {{0, 0, 1}, {s, 0, std::cos(lean * kTestPi / 180.0)}});
  EXPECT_EQ(ids[0], 0);
  expect_support_free(tree);
}

INSTANTIATE_TEST_SUITE_P(Angles, LeaningBar, ::testing::Values(40.0, 45.0));

struct WallsCase {
  std::vector<double> angles_deg;
};

class CylinderWalls : public ::testing::TestWithParam<WallsCase> {};

TEST_P(CylinderWalls, EachWallBuildsRadiallyOutwards) {
  // Cylinder r 12 (96 sides), z 0..50; walls 2 mm thick from inside the cylinder to r 32, z 5..45.
  RawMesh m = prism_z(12.0, 96, 0.0, 50.0);
  for (double a : GetParam().angles_deg) {
    m = polyaxis::test::mesh_union(m, transformed(polyaxis::test::box({11, -1, 5}, {32, 1, 45}), [&](Vec3 p) { return rotate_z(p, a); }));
  }
  const auto part = repaired(std::move(m));
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 1 + GetParam().angles_deg.size());
  expect_partition(tree, part.mesh);
  std::vector<Vec3> expected{{0, 0, 1}};
  for (double a : GetParam().angles_deg) expected.push_back({std::cos(a * kTestPi / 180.0), std::sin(a * kTestPi / 180.0), 0});
  const auto ids = match_directions(tree, expected);
  EXPECT_EQ(ids[0], 0);
  expect_support_free(tree);
}

INSTANTIATE_TEST_SUITE_P(Walls, CylinderWalls,
                         ::testing::Values(WallsCase{{40.0, 160.0, 280.0}}, WallsCase{{10.0, 100.0, 190.0, 280.0}}));

TEST(DecomposeGenerated, BodyWithRoundLugsAndKnucklesOfOtherSizes) {
  // Body 50 x 24 x 16 centred; lugs r 6 along ±Y from the body's sides to |y| = 28; two knuckles
  // 10 x 16 x 14 under the body.
  RawMesh m = polyaxis::test::box({-25, -12, -8}, {25, 12, 8});
  for (double sy : {-1.0, 1.0}) {
    const RawMesh lug = transformed(prism_z(6.0, 48, 12.0, 28.0), [&](Vec3 p) { return Vec3{p.x, sy * p.z, p.y}; });
    m = polyaxis::test::mesh_union(m, sy > 0 ? polyaxis::test::flipped(lug) : lug);  // (y, z) swapped: a mirror
  }
  for (double x : {-15.0, 15.0}) m = polyaxis::test::mesh_union(m, polyaxis::test::box({x - 5, -8, -22}, {x + 5, 8, -8}));
  const auto part = repaired(std::move(m));
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 5u);
  expect_partition(tree, part.mesh);
  const auto ids = match_directions(tree, {{0, 0, 1}, {0, 1, 0}, {0, -1, 0}, {0, 0, -1}, {0, 0, -1}});
  EXPECT_EQ(ids[0], 0);
  EXPECT_NEAR(tree.regions[0].volume_mm3, 50.0 * 24.0 * 16.0, 20.0);
  expect_support_free(tree);
}

// A column carrying a second one that starts higher up, offset sideways: the second's start face
// hangs over nothing beside the first (two_branches' +X arm in boxes). Nothing along the axis cuts
// it off; the hanging piece becomes a region of its own, built sideways from the first column.
class OffsetColumn : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(OffsetColumn, HangingStartBuildsSideways) {
  const auto [offset, start] = GetParam();
  const auto part = repaired(polyaxis::test::mesh_union(polyaxis::test::box({0, 0, 0}, {12, 12, 40}),
                                                        polyaxis::test::box({offset, 0, start}, {offset + 12, 12, start + 30})));
  const RegionTree tree = pipeline(part);
  expect_partition(tree, part.mesh);
  expect_support_free(tree);
  // What hangs, (offset × 12) mm² of start face, goes into sideways regions (build direction
  // more than 60° from +Z, towards +X), at most a few.
  double sideways = 0.0;
  for (const Region& r : tree.regions) {
    if (angle_between_deg(r.build_direction, {0, 0, 1}) > 60.0) {
      EXPECT_GT(r.build_direction.x, 0.5) << "region " << r.id;
      sideways += r.volume_mm3;
    }
  }
  // At least a millimetre of material over the whole hanging face, (offset + 12 − 12) × 12 mm².
  EXPECT_GT(sideways, offset * 12.0 * 1.0);
  EXPECT_LE(tree.regions.size(), 4u);
}

INSTANTIATE_TEST_SUITE_P(Offsets, OffsetColumn, ::testing::Values(std::pair{4.0, 25.0}, std::pair{7.0, 30.0}, std::pair{9.0, 20.0}));

// An L-block on a base plate that carries a short post under the arm: the plane that cuts the arm
// off also cuts the plate and the post, whose piece stays with the parent. The parent is that
// piece and the rest put back together as one solid, not two shells touching along the cut
// (expect_partition); a mesh of touching shells crashed the next cut.
TEST(DecomposeGenerated, ArmOverAPostLeavesTheParentOneSolid) {
  const auto base = polyaxis::test::mesh_union(polyaxis::test::box({0, 0, 0}, {60, 16, 6}), polyaxis::test::box({0, 0, 0}, {16, 16, 50}));
  const auto part = repaired(polyaxis::test::mesh_union(
      polyaxis::test::mesh_union(base, polyaxis::test::box({0, 0, 34}, {56, 16, 50})), polyaxis::test::box({40, 4, 0}, {48, 12, 20})));
  const RegionTree tree = pipeline(part);
  expect_partition(tree, part.mesh);
  expect_support_free(tree);
  const auto ids = match_directions(tree, {{0, 0, 1}, {1, 0, 0}});
  EXPECT_EQ(ids[0], 0);
  EXPECT_GE(ids[1], 1);
}

// A T: a column with a bar across its top reaching out both sides (other widths, heights and arm
// lengths). The arms' links lean towards the column's axis, so the plane across a link runs down
// through the column to the plate; the plane at the column's face removes the same overhang and
// takes only the arm. Each arm is cut there: its region is the arm alone, built straight out.
struct TeeSize {
  double half_width, height, arm, bar;  // column half-width (x), column height, arm length, bar height
};
class Tee : public ::testing::TestWithParam<TeeSize> {};

TEST_P(Tee, EachArmIsCutAtTheColumnsFace) {
  const TeeSize t = GetParam();
  constexpr double kDepth = 12.0;  // along y
  const auto part = repaired(polyaxis::test::mesh_union(
      polyaxis::test::box({-t.half_width, -kDepth / 2, 0}, {t.half_width, kDepth / 2, t.height}),
      polyaxis::test::box({-t.half_width - t.arm, -kDepth / 2, t.height - t.bar}, {t.half_width + t.arm, kDepth / 2, t.height})));
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 3u);
  expect_partition(tree, part.mesh);
  expect_support_free(tree);
  const auto ids = match_directions(tree, {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}});
  EXPECT_EQ(ids[0], 0);
  const double arm_volume = t.arm * kDepth * t.bar;
  for (const int id : {ids[1], ids[2]}) {
    ASSERT_GE(id, 1);
    EXPECT_NEAR(tree.regions[static_cast<std::size_t>(id)].volume_mm3, arm_volume, 0.01 * arm_volume) << id;
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, Tee,
                         ::testing::Values(TeeSize{5.0, 38.0, 20.0, 8.0}, TeeSize{7.0, 45.0, 25.0, 10.0}, TeeSize{4.0, 30.0, 16.0, 6.0}),
                         [](const ::testing::TestParamInfo<TeeSize>& i) {
                           return "column" + std::to_string(static_cast<int>(2 * i.param.half_width)) + "_arm" + std::to_string(static_cast<int>(i.param.arm));
                         });

// A wall carrying a shelf on its side with a round boss on the shelf (other sizes and heights).
// Built straight up, the boss overhangs along the shelf's sideways direction, and a cut along the
// shelf's underside seemed to cure it: the parent kept a film kFaceCutOffsetMm thick of the
// underside, leaning within the limit, with the shelf built upright on it. Nothing can be laid that
// thin: no region may be thinner on average than the least layer, and every region stands.
struct ShelfSize {
  double shelf_z, shelf_t, reach, boss_r;  // underside height, thickness, reach from the wall, boss radius
};
class ShelfWithBoss : public ::testing::TestWithParam<ShelfSize> {};

TEST_P(ShelfWithBoss, NoRegionIsAFilmAndEveryRegionStands) {
  const ShelfSize t = GetParam();
  constexpr double kWall = 12.0, kDepth = 40.0;
  const RawMesh boss = transformed(prism_z(t.boss_r, 40, t.shelf_z + t.shelf_t, t.shelf_z + t.shelf_t + 10.0),
                                   [&](Vec3 p) { return Vec3{p.x + kWall + 0.6 * t.reach, p.y + kDepth / 2, p.z}; });
  const auto part = repaired(polyaxis::test::mesh_union(
      polyaxis::test::mesh_union(polyaxis::test::box({0, 0, 0}, {kWall, kDepth, t.shelf_z + t.shelf_t + 4.0}),
                                 polyaxis::test::box({kWall, 0, t.shelf_z}, {kWall + t.reach, kDepth, t.shelf_z + t.shelf_t})),
      boss));
  const RegionTree tree = pipeline(part);
  ASSERT_GE(tree.regions.size(), 2u);
  expect_partition(tree, part.mesh);
  expect_support_free(tree);
  const double least = DecomposeOptions{}.min_region_mm;
  for (const Region& r : tree.regions) {
    EXPECT_GE(2.0 * mesh::signed_volume(r.mesh), least * mesh::surface_area(r.mesh)) << "region " << r.id << " is a film";
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, ShelfWithBoss,
                         ::testing::Values(ShelfSize{38.0, 8.0, 30.0, 6.0}, ShelfSize{25.0, 6.0, 22.0, 4.0}, ShelfSize{45.0, 10.0, 36.0, 8.0}),
                         [](const ::testing::TestParamInfo<ShelfSize>& i) {
                           return "reach" + std::to_string(static_cast<int>(i.param.reach)) + "_boss" + std::to_string(static_cast<int>(i.param.boss_r));
                         });

// A square column with arms on its four sides at four heights (other lengths and heights). The
// faces of the arms along X lie in one plane across the column; that plane, moved off them into the
// child, took the column, the arms along X and the arm on one side as a child built sideways, on
// films of those arms' own sides: the analysis called it support-free, and the plan started those
// arms in mid-air. Every region now stands (expect_support_free checks the bases against the
// regions below them).
struct ArmsAt {
  double z[4];  // heights of the arms' undersides: +X, −X, +Y, −Y
  double reach[4];
};
class ColumnWithFourArms : public ::testing::TestWithParam<ArmsAt> {};

TEST_P(ColumnWithFourArms, EveryArmStandsOnMaterialBelowIt) {
  const ArmsAt a = GetParam();
  constexpr double kHalf = 6.0, kArmHalf = 4.0, kArm = 8.0;
  RawMesh part = polyaxis::test::box({-kHalf, -kHalf, 0}, {kHalf, kHalf, 70});
  part = polyaxis::test::mesh_union(part, polyaxis::test::box({kHalf, -kArmHalf, a.z[0]}, {kHalf + a.reach[0], kArmHalf, a.z[0] + kArm}));
  part = polyaxis::test::mesh_union(part, polyaxis::test::box({-kHalf - a.reach[1], -kArmHalf, a.z[1]}, {-kHalf, kArmHalf, a.z[1] + kArm}));
  part = polyaxis::test::mesh_union(part, polyaxis::test::box({-kArmHalf, kHalf, a.z[2]}, {kArmHalf, kHalf + a.reach[2], a.z[2] + kArm}));
  part = polyaxis::test::mesh_union(part, polyaxis::test::box({-kArmHalf, -kHalf - a.reach[3], a.z[3]}, {kArmHalf, -kHalf, a.z[3] + kArm}));
  const auto repaired_part = repaired(std::move(part));
  const RegionTree tree = pipeline(repaired_part);
  ASSERT_GE(tree.regions.size(), 2u);
  expect_partition(tree, repaired_part.mesh);
  expect_support_free(tree);
}

INSTANTIATE_TEST_SUITE_P(Heights, ColumnWithFourArms,
                         ::testing::Values(ArmsAt{{55, 40, 25, 60}, {28, 24, 20, 32}}, ArmsAt{{20, 50, 35, 10}, {18, 30, 25, 15}},
                                           ArmsAt{{45, 45, 30, 30}, {22, 22, 22, 22}}));

}  // namespace
}  // namespace polyaxis::analysis::test

