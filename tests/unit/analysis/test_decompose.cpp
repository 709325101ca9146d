// Decomposition from given break links (the centroidal axis is tested on its own): regions,
// directions, volumes, support.
#include <gtest/gtest.h>

#include <atomic>

#include <algorithm>
#include <cmath>

#include "analysis/build_order.h"
#include "analysis/region_geometry.h"
#include "decompose_checks.h"
#include "polyaxis/analysis/decompose.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"

namespace polyaxis::analysis {
namespace {

mesh::Mesh part(const std::string& name) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name + ".stl");
  EXPECT_TRUE(read.ok());
  auto r = mesh::repair(std::move(read.value().mesh));
  EXPECT_TRUE(r.ok());
  return r.value().mesh;
}

// An axis of straight links through POINTS; the link into point BREAK_AT is a break link.
CentroidalAxis polyline_axis(const std::vector<Vec3>& points, std::size_t break_at) {
  CentroidalAxis axis;
  for (std::uint32_t i = 0; i < points.size(); ++i) axis.nodes.push_back({i, points[i], {0, 0, 1}, 0.0, 0});
  for (std::uint32_t i = 0; i + 1 < points.size(); ++i) axis.links.push_back({i, i + 1, i + 1 == break_at});
  return axis;
}

double angle_deg(Vec3 a, Vec3 b) { return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)) * 180.0 / 3.14159265358979; }

void expect_partition(const RegionTree& tree, double volume) {
  double sum = 0.0;
  for (const Region& r : tree.regions) {
    EXPECT_TRUE(mesh::build_topology(r.mesh).closed()) << "region " << r.id;
    sum += r.volume_mm3;
  }
  EXPECT_NEAR(sum, volume, 1e-3 * volume);
}

// Ruan's splitting faces are planar faces with a concave edge. The facets of a tessellated bore meet
// their neighbours at shallow concave steps (3.75° at 96 sides, 11.25° at 32): not edges of the
// part, so no facet of a tube counts; the inner corner of an L (90°) does, at any tessellation.
TEST(PlanarFaces, FacetsOfATessellatedBoreHaveNoConcaveEdgeAndAnInnerCornerHas) {
  for (const std::uint32_t sides : {32u, 96u, 400u}) {
    auto r = mesh::repair(polyaxis::test::revolve({{15.0, 0.0}, {15.0, 40.0}}, sides, 9.0));
    ASSERT_TRUE(r.ok());
    const auto faces = detail::planar_faces(r.value().mesh);
    EXPECT_GE(faces.size(), sides + 2);
    for (const detail::PlanarFace& f : faces) EXPECT_FALSE(f.concave_edge) << sides << " sides, face at " << f.point.x << " " << f.point.y;
  }
  auto l = mesh::repair(polyaxis::test::prism_xz({{0, 0}, {40, 0}, {40, 10}, {10, 10}, {10, 40}, {0, 40}}, 20.0));
  ASSERT_TRUE(l.ok());
  int creased = 0;
  for (const detail::PlanarFace& f : detail::planar_faces(l.value().mesh)) {
    const bool inner_top = f.normal.z > 0.99 && std::fabs(f.point.z - 10.0) < 1e-9 && f.area_mm2 > 500.0;
    const bool inner_side = f.normal.x > 0.99 && std::fabs(f.point.x - 10.0) < 1e-9;
    if (inner_top || inner_side) {
      EXPECT_TRUE(f.concave_edge);
      ++creased;
    }
  }
  EXPECT_EQ(creased, 2);
}

TEST(Decompose, LBlockSplitsAtThePlaneXEquals20) {
  const mesh::Mesh m = part("l_block");
  // Up the column, then turning to +X at z = 50 (the arm's mid-height).
  const auto axis = polyline_axis({{10, 10, 1}, {10, 10, 20}, {10, 10, 50}, {45, 10, 50}}, 3);
  auto tree = decompose(m, axis);
  ASSERT_TRUE(tree.ok()) << tree.error().message;
  const auto& rs = tree.value().regions;
  ASSERT_EQ(rs.size(), 2u);
  expect_partition(tree.value(), 44000.0);
  EXPECT_NEAR(rs[0].volume_mm3, 24000.0, 1.0);
  EXPECT_NEAR(rs[1].volume_mm3, 20000.0, 1.0);
  EXPECT_LT(angle_deg(rs[0].build_direction, {0, 0, 1}), 5.0);
  EXPECT_LT(angle_deg(rs[1].build_direction, {1, 0, 0}), 5.0);
  EXPECT_NEAR(rs[1].base_point.x, 20.0, 0.01);  // the cut sits 1 µm off the face, in the child
  EXPECT_EQ(rs[1].parent, 0u);
  EXPECT_EQ(rs[1].rule, "planar face");
  EXPECT_TRUE(rs[0].support_free);
  EXPECT_TRUE(rs[1].support_free);
}

// DecomposeOptions::stop: set, the decomposition ends before its first piece of work, as if its
// budget were spent (the L-block keeps one region); unset, the same call splits it.
TEST(Decompose, AStopSetEndsTheDecompositionAtItsNextPieceOfWork) {
  const mesh::Mesh m = part("l_block");
  const auto axis = polyline_axis({{10, 10, 1}, {10, 10, 20}, {10, 10, 50}, {45, 10, 50}}, 3);
  std::atomic<bool> stop{true};
  DecomposeOptions o;
  o.stop = &stop;
  auto stopped = decompose(m, axis, o);
  ASSERT_TRUE(stopped.ok()) << stopped.error().message;
  EXPECT_EQ(stopped.value().regions.size(), 1u);
  EXPECT_TRUE(stopped.value().budget_exhausted);
  stop = false;
  auto whole = decompose(m, axis, o);
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  EXPECT_EQ(whole.value().regions.size(), 2u);
  EXPECT_FALSE(whole.value().budget_exhausted);
}

TEST(Decompose, PenRackBarBuildsAlongItsIncline) {
  const mesh::Mesh m = part("pen_rack");
  const double s = std::sin(35.0 * 3.14159265358979 / 180.0), c = std::cos(35.0 * 3.14159265358979 / 180.0);
  const Vec3 dir{s, 0, c};
  // The bar's top face: the four vertices furthest along the bar; its centre is on the bar's axis.
  std::vector<Vec3> v = m.vertices;
  std::sort(v.begin(), v.end(), [&](Vec3 a, Vec3 b) { return core::dot(a, dir) > core::dot(b, dir); });
  const Vec3 top = (v[0] + v[1] + v[2] + v[3]) / 4.0;
  const Vec3 start = top - dir * ((top.z - 6.0) / c);  // where the bar's axis meets the plate top (z = 6)
  const auto axis = polyline_axis({start - Vec3{0, 0, 5}, start, start + dir * 5.0, start + dir * 30.0}, 2);
  auto tree = decompose(m, axis);
  ASSERT_TRUE(tree.ok()) << tree.error().message;
  const auto& rs = tree.value().regions;
  // The plate, the bar's corner that pokes 0.7 mm through the plate's bottom (built downwards
  // from the plate), and the bar.
  ASSERT_EQ(rs.size(), 3u);
  expect_partition(tree.value(), mesh::signed_volume(m));
  EXPECT_EQ(rs[1].rule, "below the plate");
  EXPECT_LT(angle_deg(rs[1].build_direction, {0, 0, -1}), 1e-9);
  EXPECT_LT(rs[1].volume_mm3, 50.0);  // a wedge 0.74 mm deep under a 10 x 20 mm section
  EXPECT_LT(angle_deg(rs[2].build_direction, dir), 5.0);
  EXPECT_GT(rs[2].volume_mm3, 10000.0);
  for (const Region& r : rs) EXPECT_TRUE(r.support_free) << "region " << r.id << ": " << r.unsupported_area_mm2;
}

}  // namespace
}  // namespace polyaxis::analysis

// The full pipeline (centroidal axis + decomposition, as `polyaxis analyze`) on the reference parts
// (parts/README.md).
namespace polyaxis::analysis::test {
namespace {

TEST(DecomposePipeline, LBlock) {
  const auto part = reference_part("l_block");
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 2u);
  expect_partition(tree, part.mesh);
  const auto ids = match_directions(tree, {{0, 0, 1}, {1, 0, 0}});
  EXPECT_EQ(ids[0], 0);
  EXPECT_NEAR(tree.regions[0].volume_mm3, 24000.0, 24.0);
  EXPECT_NEAR(tree.regions[1].volume_mm3, 20000.0, 20.0);
  EXPECT_NEAR(tree.regions[1].base_point.x, 20.0, 0.01);
  expect_support_free(tree);
}

TEST(DecomposePipeline, PenRackBarAlongItsIncline) {
  const auto part = reference_part("pen_rack");
  const RegionTree tree = pipeline(part);
  // The plate, the bar's corner poking 0.74 mm through the plate's bottom, and the bar.
  ASSERT_EQ(tree.regions.size(), 3u);
  expect_partition(tree, part.mesh);
  const double t = 35.0 * kTestPi / 180.0;
  const auto ids = match_directions(tree, {{0, 0, 1}, {0, 0, -1}, {std::sin(t), 0, std::cos(t)}});
  EXPECT_EQ(ids[0], 0);
  if (ids[1] >= 0) {
    EXPECT_LT(tree.regions[ids[1]].volume_mm3, 50.0);
  }
  if (ids[2] >= 0) {
    EXPECT_GT(tree.regions[ids[2]].volume_mm3, 10000.0);
  }
  expect_support_free(tree);
}

TEST(DecomposePipeline, HingeBodyLugsAndKnuckles) {
  const auto part = reference_part("hinge");
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 5u);
  expect_partition(tree, part.mesh);
  const auto ids = match_directions(tree, {{0, 0, 1}, {0, 1, 0}, {0, -1, 0}, {0, 0, -1}, {0, 0, -1}});
  EXPECT_EQ(ids[0], 0);
  EXPECT_NEAR(tree.regions[0].volume_mm3, 60.0 * 30.0 * 20.0, 36.0);  // the body: the lugs start at y = ±15
  for (int i : {ids[3], ids[4]}) {
    if (i >= 0) {
      EXPECT_NEAR(tree.regions[i].volume_mm3, 12.0 * 20.0 * 16.0, 4.0);  // a knuckle
    }
  }
  expect_support_free(tree);
}

TEST(DecomposePipeline, CylinderWithFiveWallsMatchesDwivediTable1) {
  const auto part = reference_part("cyl_walls5");
  const RegionTree tree = pipeline(part);
  ASSERT_EQ(tree.regions.size(), 6u);
  expect_partition(tree, part.mesh);
  // Dwivedi & Kovacevic Table 1: orientation vectors and platform rotation angles.
  const std::vector<Vec3> table = {{-0.95, 0.31, 0}, {-0.59, -0.81, 0}, {0.59, -0.81, 0}, {0.95, 0.31, 0}, {0, 1, 0}};
  const double rotation_deg[] = {162, -126, -54, 18, 90};
  std::vector<Vec3> expected{{0, 0, 1}};
  expected.insert(expected.end(), table.begin(), table.end());
  const auto ids = match_directions(tree, expected);
  EXPECT_EQ(ids[0], 0);
  for (std::size_t k = 0; k < table.size(); ++k) {
    if (ids[k + 1] < 0) continue;
    const Vec3 d = tree.regions[ids[k + 1]].build_direction;
    const double angle = std::atan2(d.y, d.x) * 180.0 / kTestPi;
    EXPECT_NEAR(angle, rotation_deg[k], kDirectionToleranceDeg) << "wall " << k;
    EXPECT_NEAR(tree.regions[ids[k + 1]].volume_mm3, 2500.0, 25.0);  // 25 x 2 x 50 beyond r = 15
  }
  expect_support_free(tree);
}

// The +X arm of this part starts 15° from vertical beside the −X arm (its start face, about 22 mm²,
// hangs in the air) and ends horizontal: 75° of turn cannot be built support-free at 30° in one
// direction, so the decomposition gives regions that are not all support-free, and says so.
TEST(DecomposePipeline, TwoBranchesTrunkTwoArmsAndTheHangingStartOfOne) {
  const auto part = reference_part("two_branches");
  const RegionTree tree = pipeline(part);
  expect_partition(tree, part.mesh);
  // No facet overhangs; but one sideways piece starts on nothing at one corner, the end of the keel
  // where its cut meets the +X arm's start disc (the plan's layers find the same island there).
  int starting_in_air = 0;
  const Vec3 disc_centre{40.0 + 40.0 * std::cos(165.0 * kTestPi / 180.0), 0, 30.0 + 40.0 * std::sin(165.0 * kTestPi / 180.0)};
  const Vec3 disc_normal{std::sin(165.0 * kTestPi / 180.0), 0, -std::cos(165.0 * kTestPi / 180.0)};  // the arm's start tangent
  for (const Region& r : tree.regions) {
    EXPECT_EQ(r.unsupported_area_mm2, 0.0) << "region " << r.id;
    EXPECT_EQ(r.support_free, r.mid_air_starts.empty()) << "region " << r.id;
    if (r.mid_air_starts.empty()) continue;
    ++starting_in_air;
    EXPECT_EQ(r.rule, "overhang patch");
    for (const Vec3& p : r.mid_air_starts) EXPECT_NEAR(core::dot(p - disc_centre, disc_normal), 0.0, 0.05);
  }
  EXPECT_LE(starting_in_air, 1);
  EXPECT_LT(angle_between_deg(tree.regions[0].build_direction, {0, 0, 1}), 1e-9);
  // The root is the trunk (r 6, 30 tall) with the junction where the arms leave it.
  EXPECT_GT(tree.regions[0].volume_mm3, 0.99 * kTestPi * 36.0 * 30.0);
  EXPECT_LT(tree.regions[0].volume_mm3, mesh::signed_volume(part.mesh) / 3.0);
  // The arms: each leans outwards, between its ends' tangents (0°..75° and 15°..90° from vertical),
  // and holds most of its arm (each arm alone is about 5 400 mm³).
  int left = 0, right = 0;
  for (const Region& r : tree.regions) {
    if (r.id == 0 || r.volume_mm3 < 4000.0) continue;
    const double lean = angle_between_deg(r.build_direction, {0, 0, 1});
    EXPECT_GT(lean, 30.0);
    EXPECT_LT(lean, 75.0);
    (r.build_direction.x < 0 ? left : right) += 1;
  }
  EXPECT_EQ(left, 1);
  EXPECT_EQ(right, 1);
  // The +X arm starts 15° up the arc beside the -X arm: its start face hangs over nothing where the
  // -X arm does not reach under it (21.5 mm², facing 15° from straight down). No planar region can
  // hold it with the arm; it is built sideways (+X) as small regions of its own (at most two, 4% of
  // the part).
  double patches = 0.0;
  int patch_regions = 0;
  for (const Region& r : tree.regions) {
    if (r.rule != "overhang patch") continue;
    ++patch_regions;
    patches += r.volume_mm3;
    EXPECT_GT(r.build_direction.x, 0.5) << "region " << r.id;
  }
  EXPECT_GE(patch_regions, 1);
  EXPECT_LE(patch_regions, 2);
  EXPECT_LT(patches, 0.04 * mesh::signed_volume(part.mesh));
}

}  // namespace
}  // namespace polyaxis::analysis::test

namespace polyaxis::analysis {
namespace {

// --root-base: the root stands where the user says.
RegionTree pinned(const mesh::RepairedMesh& part, const RootBase& base) {
  auto up = root_direction(part.mesh, base, {0, 0, 1});
  EXPECT_TRUE(up.ok());
  CentroidalAxisOptions ao;
  const Vec3 d = up.value();
  ao.start_direction = std::fabs(d.z) >= std::fabs(d.x) && std::fabs(d.z) >= std::fabs(d.y) ? Vec3{0, 0, d.z < 0 ? -1.0 : 1.0}
                       : std::fabs(d.y) >= std::fabs(d.x)                                    ? Vec3{0, d.y < 0 ? -1.0 : 1.0, 0}
                                                                                             : Vec3{d.x < 0 ? -1.0 : 1.0, 0, 0};
  auto axis = centroidal_axis(part.mesh, part.topology, ao);
  EXPECT_TRUE(axis.ok());
  DecomposeOptions o;
  o.root_base = base;
  auto tree = decompose(part.mesh, axis.value(), o);
  EXPECT_TRUE(tree.ok()) << tree.error().message;
  return tree.value();
}

TEST(DecomposeRootBase, LBlockStandingOnTheArmsEndBuildsTheColumnDownwards) {
  const mesh::RepairedMesh part = test::reference_part("l_block");
  const auto faces = base_faces(part.mesh);
  const BaseFace* end = nullptr;
  for (const BaseFace& f : faces) {
    if (f.normal.x > 0.999 && f.point.x > 69.999) end = &f;  // the arm's end, x = 70
  }
  ASSERT_NE(end, nullptr);
  RootBase base;
  base.kind = RootBase::Kind::kFace;
  base.face = end->id;
  const RegionTree tree = pinned(part, base);
  ASSERT_EQ(tree.regions.size(), 2u);
  test::expect_partition(tree, part.mesh);
  test::expect_support_free(tree);
  EXPECT_LT(test::angle_between_deg(tree.regions[0].build_direction, {-1, 0, 0}), 1e-6);
  EXPECT_NEAR(core::dot(tree.regions[0].base_point, {1, 0, 0}), 70.0, 1e-6);
  EXPECT_LT(test::angle_between_deg(tree.regions[1].build_direction, {0, 0, -1}), 5.0);  // the column, hanging from the arm
  EXPECT_EQ(tree.faces.size(), faces.size());
}

TEST(DecomposeRootBase, PlaneThroughTheColumnLeavesItsFootBuiltDownwards) {
  const mesh::RepairedMesh part = test::reference_part("l_block");
  RootBase base;
  base.kind = RootBase::Kind::kPlane;
  base.point = {10, 10, 30};
  base.normal = {0, 0, 2};  // any length
  const RegionTree tree = pinned(part, base);
  ASSERT_EQ(tree.regions.size(), 3u);
  test::expect_partition(tree, part.mesh);
  test::expect_support_free(tree);
  EXPECT_NEAR(tree.regions[0].volume_mm3, 12000.0, 1.0);  // the column above z = 30 ...
  EXPECT_NEAR(tree.regions[1].volume_mm3, 12000.0, 1.0);  // ... the foot below, built along −Z
  EXPECT_LT(test::angle_between_deg(tree.regions[1].build_direction, {0, 0, -1}), 1e-6);
  EXPECT_NEAR(tree.regions[2].volume_mm3, 20000.0, 1.0);  // the arm, along +X
}

TEST(DecomposeRootBase, LowestPointMatchesThePlateOnAFlatBottomedPart) {
  const mesh::RepairedMesh part = test::reference_part("l_block");
  RootBase base;
  base.kind = RootBase::Kind::kLowest;
  const RegionTree tree = pinned(part, base);
  ASSERT_EQ(tree.regions.size(), 2u);
  EXPECT_NEAR(tree.regions[0].volume_mm3, 24000.0, 1.0);
}

TEST(DecomposeRootBase, UnknownFaceOrZeroNormalIsAUsageError) {
  const mesh::RepairedMesh part = test::reference_part("l_block");
  RootBase base;
  base.kind = RootBase::Kind::kFace;
  base.face = 12345;
  auto d = root_direction(part.mesh, base, {0, 0, 1});
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().code, core::ErrorCode::kUsage);
  EXPECT_NE(d.error().message.find("--root-base"), std::string::npos);
  base.kind = RootBase::Kind::kPlane;
  base.normal = {0, 0, 0};
  EXPECT_FALSE(root_direction(part.mesh, base, {0, 0, 1}).ok());
}

}  // namespace
}  // namespace polyaxis::analysis

namespace polyaxis::analysis {
namespace {

// Two regions whose bases each lie on the other (a cycle, which decompose does not make): the
// build order breaks it at the lower one and keeps its promise for what rests_on lists.
TEST(BuildOrder, ACycleIsBrokenAndRestsOnStillHolds) {
  auto region = [](std::uint32_t id, std::optional<std::uint32_t> parent, io::RawMesh box, Vec3 base_point, Vec3 base_normal) {
    Region r;
    r.id = id;
    r.parent = parent;
    r.mesh = test::repaired(std::move(box)).mesh;
    r.base_point = base_point;
    r.base_normal = base_normal;
    return r;
  };
  std::vector<Region> regions;
  regions.push_back(region(0, std::nullopt, polyaxis::test::box({100, 0, 0}, {110, 10, 10}), {100, 0, 0}, {0, 0, 1}));
  // A stands on B's top (base z = 10, built up); B hangs from A's underside (base z = 10, built down).
  regions.push_back(region(1, 0, polyaxis::test::box({10, 0, 10}, {30, 10, 20}), {0, 0, 10}, {0, 0, 1}));
  regions.push_back(region(2, 0, polyaxis::test::box({0, 0, 0}, {20, 10, 10}), {0, 0, 10}, {0, 0, -1}));
  detail::order_by_support(regions);
  ASSERT_EQ(regions.size(), 3u);
  std::size_t listed_other = 0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    EXPECT_EQ(regions[i].id, i);
    for (std::uint32_t below : regions[i].rests_on) EXPECT_LT(below, i);
    if (i > 0) {
      ASSERT_TRUE(regions[i].parent.has_value());
      EXPECT_NE(std::find(regions[i].rests_on.begin(), regions[i].rests_on.end(), *regions[i].parent), regions[i].rests_on.end());
      listed_other += regions[i].rests_on.size() - 1;
    }
  }
  EXPECT_EQ(regions[0].id, 0u);
  EXPECT_TRUE(regions[0].rests_on.empty());
  EXPECT_EQ(listed_other, 1u);  // the later one rests on the earlier; the earlier's wait was dropped
}

}  // namespace
}  // namespace polyaxis::analysis

