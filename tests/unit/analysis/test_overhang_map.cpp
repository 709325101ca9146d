// Overhang map (SPEC §2.2): totals agree with mesh::overhang_area, patches on the reference parts.
#include "polyaxis/analysis/overhang_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "polyaxis/core/tolerances.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "support/meshes.h"

namespace polyaxis::analysis {
namespace {

const double kAlpha = core::kDefaultSelfSupportingDeg * std::numbers::pi / 180.0;

mesh::RepairedMesh part(const std::string& name) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name + ".stl");
  EXPECT_TRUE(read.ok()) << name;
  auto r = mesh::repair(std::move(read.value().mesh));
  EXPECT_TRUE(r.ok()) << name;
  return std::move(r).value();
}

mesh::RepairedMesh made(io::RawMesh raw) {
  auto r = mesh::repair(std::move(raw));
  EXPECT_TRUE(r.ok());
  return std::move(r).value();
}

// Totals, facet lists and patch sums are consistent with each other and with mesh::overhang_area.
void expect_consistent(const mesh::RepairedMesh& rm, const OverhangMap& map, Vec3 d) {
  EXPECT_EQ(map.area_mm2, mesh::overhang_area(rm.mesh, d, kAlpha));  // same arithmetic, same order
  std::size_t facets = 0;
  double area = 0.0;
  for (const OverhangPatch& p : map.patches) {
    facets += p.facets.size();
    area += p.area_mm2;
    EXPECT_LE(p.lowest_mm, p.highest_mm);
    EXPECT_NEAR(norm(p.mean_normal), 1.0, 1e-12);
    EXPECT_LT(dot(p.mean_normal, map.build_direction), -std::sin(kAlpha) + 1e-12);
  }
  EXPECT_EQ(facets, map.facets.size());
  EXPECT_NEAR(area, map.area_mm2, 1e-9 * (1.0 + map.area_mm2));
}

TEST(OverhangMap, LBlockHasOnePatchUnderTheArm) {
  const auto rm = part("l_block");
  const OverhangMap map = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  expect_consistent(rm, map, {0, 0, 1});
  ASSERT_EQ(map.patches.size(), 1u);
  const OverhangPatch& p = map.patches[0];
  EXPECT_NEAR(p.area_mm2, 1000.0, 1e-9);  // 50 × 20 under the arm
  EXPECT_DOUBLE_EQ(p.lowest_mm, 40.0);
  EXPECT_DOUBLE_EQ(p.highest_mm, 40.0);
  EXPECT_NEAR(p.centroid.x, 45.0, 1e-9);
  EXPECT_NEAR(p.centroid.y, 10.0, 1e-9);
  EXPECT_NEAR(p.centroid.z, 40.0, 1e-9);
  EXPECT_NEAR(p.mean_normal.z, -1.0, 1e-12);
}

TEST(OverhangMap, BoxHasNone) {
  const auto rm = made(test::box({0, 0, 0}, {30, 20, 10}));
  const OverhangMap map = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  EXPECT_TRUE(map.facets.empty());
  EXPECT_TRUE(map.patches.empty());
  EXPECT_EQ(map.area_mm2, 0.0);
}

TEST(OverhangMap, BoxHasNoneInAnyAxisDirection) {
  // Along every axis direction the face facing away from d rests on the plate.
  const auto rm = made(test::box({0, 0, 0}, {30, 20, 10}));
  for (const Vec3 d : {Vec3{0, 0, -1}, Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}}) {
    const OverhangMap map = overhang_map(rm.mesh, rm.topology, d, kAlpha);
    EXPECT_TRUE(map.patches.empty());
    EXPECT_EQ(map.area_mm2, 0.0);
  }
}

TEST(OverhangMap, TiltedBoxOverhangsItsLowerFaces) {
  // Tilted 45° about Y, a box's underside faces (−1, 0, −1)/√2: n·d = −0.71 < −sin 30°.
  const auto rm = made(test::box({0, 0, 0}, {30, 20, 10}));
  const Vec3 d = core::normalized({1, 0, 1});
  const OverhangMap map = overhang_map(rm.mesh, rm.topology, d, kAlpha);
  expect_consistent(rm, map, d);
  // Faces x = 0 (normal −X) and z = 0 (normal −Z) both have n·d = −0.71; the lowest point along d
  // is the edge x = z = 0, and neither face lies wholly on it. They share that edge: one patch.
  ASSERT_EQ(map.patches.size(), 1u);
  EXPECT_NEAR(map.area_mm2, 20.0 * 10.0 + 30.0 * 20.0, 1e-9);
  EXPECT_NEAR(map.patches[0].lowest_mm, 0.0, 1e-12);
}

TEST(OverhangMap, CylWalls5HasOnePatchUnderEachWall) {
  const auto rm = part("cyl_walls5");
  const OverhangMap map = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  expect_consistent(rm, map, {0, 0, 1});
  ASSERT_EQ(map.patches.size(), 5u);
  std::vector<int> seen(5, 0);
  for (const OverhangPatch& p : map.patches) {
    EXPECT_NEAR(p.lowest_mm, 5.0, 1e-4);
    EXPECT_NEAR(p.highest_mm, 5.0, 1e-4);
    EXPECT_NEAR(p.area_mm2, 2.0 * 25.0, 0.5);  // 2 mm × (40 − 15) mm, less the cylinder's curvature
    const double angle_deg = std::atan2(p.centroid.y, p.centroid.x) * 180.0 / std::numbers::pi;
    const double k = std::round((angle_deg - 18.0) / 72.0);
    EXPECT_NEAR(angle_deg, 18.0 + 72.0 * k, 0.5);
    ++seen[static_cast<std::size_t>((static_cast<int>(k) % 5 + 5) % 5)];
  }
  for (const int s : seen) EXPECT_EQ(s, 1);
}

TEST(OverhangMap, HingeHasSeveralPatches) {
  const auto rm = part("hinge");
  const OverhangMap map = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  expect_consistent(rm, map, {0, 0, 1});
  // The body's underside around the knuckles, the underside of each lug, the top of each bore.
  EXPECT_GE(map.patches.size(), 3u);
  bool body = false;
  for (const OverhangPatch& p : map.patches) body = body || (std::abs(p.lowest_mm + 10.0) < 1e-4 && p.highest_mm == p.lowest_mm);
  EXPECT_TRUE(body);
}

TEST(OverhangMap, EveryPartAgreesWithOverhangAreaInSixDirections) {
  for (const char* name : {"cyl_walls5", "dome_sphere", "hinge", "impeller", "l_block", "pen_rack", "spiral", "two_branches"}) {
    const auto rm = part(name);
    for (const Vec3 d : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0.3, -0.4, 0.866}}) {
      SCOPED_TRACE(name);
      expect_consistent(rm, overhang_map(rm.mesh, rm.topology, d, kAlpha), normalized(d));
    }
  }
}

TEST(OverhangMap, PenRackBarOverhangsAtThirtyFiveDegrees) {
  const auto rm = part("pen_rack");
  const OverhangMap map = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  expect_consistent(rm, map, {0, 0, 1});
  ASSERT_GE(map.patches.size(), 1u);
  // At α = 40° a bar leaning 35° is self-supporting.
  const double a40 = 40.0 * std::numbers::pi / 180.0;
  EXPECT_LT(overhang_map(rm.mesh, rm.topology, {0, 0, 1}, a40).area_mm2, map.area_mm2);
}

TEST(OverhangMap, DeterministicAcrossCalls) {
  const auto rm = part("impeller");
  const OverhangMap a = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  const OverhangMap b = overhang_map(rm.mesh, rm.topology, {0, 0, 1}, kAlpha);
  ASSERT_EQ(a.patches.size(), b.patches.size());
  for (std::size_t i = 0; i < a.patches.size(); ++i) {
    EXPECT_EQ(a.patches[i].facets, b.patches[i].facets);
    EXPECT_EQ(a.patches[i].centroid, b.patches[i].centroid);
  }
}

}  // namespace
}  // namespace polyaxis::analysis
