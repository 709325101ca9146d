// The build order (planner/sequence.h): C-space contours, interference levels, brothers built
// level by level where one built to its end would be struck by the head building the other, and
// the read-back verification agreeing.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "planner/sequence.h"
#include "polyaxis/planner/plan.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/verify/verify.h"
#include "support/meshes.h"
#include "support/programs.h"
#include "support/readback.h"
#include "support/repaired.h"

namespace polyaxis::planner {
namespace {

using detail::Sequence;
using detail::sequence_layers;
using test::box;

mesh::Mesh mesh_of(const io::RawMesh& raw) { return test::repaired(raw).mesh; }

// A square of side S centred at the origin of a layer in the plane through ORIGIN normal to D.
slicing::Layer square_layer(Vec3 d, Vec3 origin, double s) {
  slicing::Layer l;
  l.frame = slicing::plane_frame(d, core::dot(origin, core::normalized(d)));
  l.frame.origin = origin;
  l.height_mm = core::dot(origin, l.frame.d);
  l.below_mm = l.above_mm = 0.25;
  const std::int64_t h = geom2d::to_units(0.5 * s);
  l.polygons.push_back({{{-h, -h}, {h, -h}, {h, h}, {-h, h}}, {}});
  l.area_mm2 = s * s;
  return l;
}

std::vector<PlanRegion> three_regions() {
  std::vector<PlanRegion> r(3);
  r[0].id = 0, r[1].id = 1, r[2].id = 2;
  r[1].parent = 0, r[2].parent = 0;
  return r;
}

// In build order, layer K's paths and the pieces no bead covers carry K (they are numbered again
// when the layers of all regions are put in order): an L whose arm, built along X, carries a fin
// 0.3 mm thick, too thin to lay, 10 mm beyond its end.
TEST(Sequence, EveryLayerInBuildOrderCarriesItsIndexOnItsPathsAndThinPieces) {
  PlanPartOptions o;
  o.strategy = Strategy::kDecompose;
  const auto part = test::repaired(test::prism_xz({{0, 0}, {10, 0}, {10, 14}, {30, 14}, {30, 16.85}, {40, 16.85}, {40, 17.15}, {30, 17.15}, {30, 20}, {0, 20}}, 16.0));
  auto r = plan_part(part, test::example_machine("ded5_ac"), test::default_process(), o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Plan& plan = r.value().plan;
  ASSERT_GE(plan.regions, 2u);
  std::size_t thin = 0;
  for (std::size_t k = 0; k < plan.toolpaths.size(); ++k) {
    const toolpath::LayerToolpaths& lt = plan.toolpaths[k];
    EXPECT_EQ(lt.layer, k);
    for (const toolpath::Path& path : lt.paths) EXPECT_EQ(path.layer, k);
    for (const toolpath::ThinRegion& t : lt.thin) {
      EXPECT_EQ(t.layer, k);
      ++thin;
    }
  }
  EXPECT_EQ(thin, plan.thin_regions);
  EXPECT_GT(thin, 0u);
}

TEST(Sequence, CrossingLayersInterfereWhenTheirGrownContoursMeetOnTheLineTheirPlanesShare) {
  // A horizontal 10 mm square at the origin and a vertical one (normal +X) in the plane GAP beyond
  // the first's edge, both grown by 5 mm: the planes meet on the line x = 5 + gap, which the first's
  // grown contour reaches while the gap is under 5 mm (the second's spans z = 3 ± 10 there).
  for (const double gap : {2.0, 4.5, 5.5, 9.0, 30.0}) {
    const std::vector<slicing::Layer> layers{square_layer({0, 0, 1}, {0, 0, 0}, 10.0), square_layer({1, 0, 0}, {5.0 + gap, 0, 3}, 10.0)};
    const Sequence s = sequence_layers(layers, {1, 2}, three_regions(), 5.0, true);
    const bool expect = gap < 5.0;
    EXPECT_EQ(s.records[0].interferences, expect ? 1u : 0u) << gap;
    EXPECT_EQ(s.records[1].level, expect ? 1u : 0u) << gap;
  }
}

TEST(Sequence, ParallelLayersInterfereOnlyInOneSlab) {
  // Two coplanar squares 20 mm apart grown by 12 mm overlap; lifted by a layer they do not.
  const std::vector<slicing::Layer> flat{square_layer({0, 0, 1}, {0, 0, 5}, 10.0), square_layer({0, 0, 1}, {30, 0, 5}, 10.0)};
  EXPECT_EQ(sequence_layers(flat, {1, 2}, three_regions(), 12.0, true).records[0].interferences, 1u);
  EXPECT_EQ(sequence_layers(flat, {1, 2}, three_regions(), 9.0, true).records[0].interferences, 0u);
  const std::vector<slicing::Layer> lifted{square_layer({0, 0, 1}, {0, 0, 5}, 10.0), square_layer({0, 0, 1}, {30, 0, 6}, 10.0)};
  EXPECT_EQ(sequence_layers(lifted, {1, 2}, three_regions(), 12.0, true).records[0].interferences, 0u);
}

TEST(Sequence, AFatherAndItsChildNeverInterfereAndTheChildWaits) {
  // Region 1 (child of 0) listed first in the layers would still come after all of region 0.
  std::vector<slicing::Layer> layers;
  for (int k = 0; k < 3; ++k) layers.push_back(square_layer({0, 0, 1}, {0, 0, 0.5 * k}, 10.0));
  for (int k = 0; k < 3; ++k) layers.push_back(square_layer({0, 0, 1}, {0, 0, 1.5 + 0.5 * k}, 10.0));
  std::vector<PlanRegion> regions(2);
  regions[0].id = 0, regions[1].id = 1, regions[1].parent = 0;
  const Sequence s = sequence_layers(layers, {0, 0, 0, 1, 1, 1}, regions, 25.0, true);
  EXPECT_EQ(s.order, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
  for (const LayerOrder& r : s.records) EXPECT_EQ(r.interferences, 0u);
  EXPECT_EQ(s.records[0].rule, kRuleStart);
  EXPECT_EQ(s.records[3].rule, kRuleFather);
  EXPECT_EQ(s.records[4].rule, kRuleContinue);
}

// A block with two parallel walls on it, GAP apart, each a region of its own built upwards: the
// default head (cylinder r 25 mm, 20 mm above the tip) building one wall's first layers reaches
// over the other wall's full height when that one is built first.
struct TwoWalls {
  Plan plan;
  verify::BuildCheck check;
  test::ReadBack read_back;  // the tests' own brute-force reading, head against deposit included
};

// READ_BACK: also the tests' own brute-force reading (head against every earlier deposit sample).
TwoWalls plan_two_walls(double gap, bool interleave, bool read_back = false) {
  const io::RawMesh root = box({0, 0, 0}, {40 + gap, 20, 6}), a = box({10, 4, 6}, {12, 16, 36}), b = box({12 + gap, 4, 6}, {14 + gap, 16, 36});
  std::vector<PlanRegion> regions(3);
  const io::RawMesh parts[3] = {root, a, b};
  for (std::uint32_t i = 0; i < 3; ++i) {
    regions[i].id = i;
    regions[i].mesh = mesh_of(parts[i]);
    regions[i].direction = {0, 0, 1};
    if (i > 0) regions[i].parent = 0, regions[i].rests_on = {0};
  }
  const machine::MachineConfig m = machine::parse_machine(machine::default_machine_json(), "default").value();
  process::ProcessConfig p = test::default_process();
  p.rules.interleave = interleave;
  PlanOptions o;
  auto plan = make_plan(test::repaired(test::join(test::join(root, a), b)), m, p, o, regions);
  EXPECT_TRUE(plan.ok()) << plan.error().message;
  TwoWalls out{std::move(plan.value()), {}, {}};
  auto gcode = post::write_gcode(m, p, out.plan.program);
  EXPECT_TRUE(gcode.ok()) << gcode.error().message;
  auto check = verify::verify_build(m, p, out.plan.build_model, gcode.value());
  EXPECT_TRUE(check.ok());
  out.check = check.value();
  const machine::SubstratePlate& plate = out.plan.build_model.substrate;
  const test::Plate pl{plate.x_min_mm, plate.x_max_mm, plate.y_min_mm, plate.y_max_mm, plate.top_z_mm, out.plan.build_model.table_top_z_mm()};
  if (read_back) out.read_back = test::read_back(m, p, pl, gcode.value(), 1.1, 0.45, true);
  return out;
}

// How often the build switches between the walls (regions 1 and 2).
int switches(const Plan& plan) {
  int n = 0;
  for (std::size_t k = 1; k < plan.region_of_layer.size(); ++k) {
    const std::uint32_t a = plan.region_of_layer[k - 1], b = plan.region_of_layer[k];
    n += (a != b && a > 0 && b > 0) ? 1 : 0;
  }
  return n;
}

TEST(Sequence, CloseWallsAreBuiltLevelByLevelAndVerifyCleanWhereOneAfterTheOtherCollides) {
  const TwoWalls together = plan_two_walls(16.0, true, true);
  std::size_t wall_layers = 0;
  for (const std::uint32_t r : together.plan.region_of_layer) wall_layers += r > 0 ? 1 : 0;
  ASSERT_GT(wall_layers, 40u);
  // L1R1, L1R2, L2R1, L2R2 …: a switch at every layer, each pair on one level.
  EXPECT_GE(switches(together.plan), static_cast<int>(wall_layers) - 2);
  for (std::size_t k = 0; k < together.plan.order.size(); ++k) {
    const LayerOrder& o = together.plan.order[k];
    if (o.region == 0) continue;
    EXPECT_EQ(o.level, o.region_layer) << k;
    EXPECT_TRUE(o.rule == kRuleFather || o.rule == kRuleLevel) << k << " " << o.rule;
    EXPECT_GT(o.interferences, 0u);
  }
  EXPECT_EQ(together.check.material_collisions, 0u);
  EXPECT_EQ(together.check.head_collisions, 0u);
  EXPECT_EQ(together.check.ungrounded_samples, 0u);
  EXPECT_EQ(together.read_back.head_in_deposit, 0u) << together.read_back.first_problem;
  EXPECT_EQ(together.read_back.head_below, 0u) << together.read_back.first_problem;

  // One wall to its end, then the other: the head strikes the first wall.
  const TwoWalls apart = plan_two_walls(16.0, false, true);
  EXPECT_EQ(switches(apart.plan), 1);
  EXPECT_GT(apart.check.material_collisions, 0u);
  EXPECT_GT(apart.read_back.head_in_deposit, 0u);
}

TEST(Sequence, WallsFartherApartThanTheHeadIsWideAreEachBuiltToTheirEnd) {
  const TwoWalls far = plan_two_walls(60.0, true);
  EXPECT_EQ(switches(far.plan), 1);
  for (const LayerOrder& o : far.plan.order) EXPECT_EQ(o.level, 0u);
  EXPECT_EQ(far.check.material_collisions, 0u);
}

// Auto's choice makes the decomposition rooted at the part's lowest point only when the one rooted
// as found stands elsewhere (it would be the same tree), whether that one plans or not: a ring
// lying flat (its root at its lowest point, one region) is decomposed once each way up, a table
// on four legs (rooted at the top's underside, above its feet) from its lowest point too.
TEST(AutoChoice, TheDecompositionFromTheLowestPointIsMadeOnlyWhereItsRootDiffers) {
  PlanPartOptions o;
  auto ring = plan_part(test::repaired(test::torus(20.0, 5.0, 48, 24)), test::example_machine("ded5_ac"), test::default_process(), o);
  ASSERT_TRUE(ring.ok()) << ring.error().message;
  EXPECT_NE(ring.value().choice.find("the decomposition: it finds the part one region"), std::string::npos) << ring.value().choice;
  EXPECT_EQ(ring.value().choice.find("from the lowest point"), std::string::npos) << ring.value().choice;
  io::RawMesh table = box({0, 0, 12}, {30, 30, 15});
  for (const double x : {0.0, 25.0}) {
    for (const double y : {0.0, 25.0}) table = test::join(std::move(table), box({x, y, 0}, {x + 5, y + 5, 12}));
  }
  auto legs = plan_part(test::repaired(table), test::example_machine("ded5_ac"), test::default_process(), o);
  ASSERT_TRUE(legs.ok()) << legs.error().message;
  EXPECT_NE(legs.value().choice.find("from the lowest point"), std::string::npos) << legs.value().choice;
}

// choose_s is all of plan_part but the kept program's G-code, simulation and verification: a plan
// whose choice is made twice (a ring that overhangs: the choice again on planar layers) counts both,
// and the four figures add up to the whole call. (Where a decomposition was dropped after its
// read-back for one direction, choose_s was 0.)
TEST(AutoChoice, TheChoiceTimeIsAllButTheKeptProgramsReadBack) {
  const auto ring = test::repaired(test::torus(16.0, 4.0, 40, 20));
  const auto t0 = std::chrono::steady_clock::now();
  auto r = plan_part(ring, test::example_machine("ded5_ac"), test::default_process(), PlanPartOptions{});
  const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.error().message;
  const PlanPartResult& p = r.value();
  const StageTimes& t = p.plan.times;
  EXPECT_GE(p.choose_s, t.slice_s + t.toolpath_s + t.sequence_s + t.support_s + t.fidelity_s + t.program_s);
  EXPECT_NEAR(p.choose_s + p.gcode_s + p.simulate_s + p.verify_s, whole, 0.01 * whole + 0.01);
}

}  // namespace
}  // namespace polyaxis::planner
