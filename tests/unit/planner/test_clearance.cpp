// The planner's own clearance checks (planner/clearance.h): the moves the program makes, checked
// before any G-code exists, so that the read-back verification finds nothing left to relieve.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "planner/clearance.h"
#include "planner/reach.h"
#include "polyaxis/machine/build_model.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/verify/deposit_check.h"
#include "support/meshes.h"
#include "support/programs.h"
#include "support/repaired.h"

namespace polyaxis::planner::detail {
namespace {

constexpr double kBead = 1.2;
constexpr double kDeg = std::numbers::pi / 180.0;

// A wall of beads along Y at X = 20, LAYERS layers of 0.6 mm from the plate's top, 20 mm long:
// planned points, the wall laid before the travel (its points come first).
std::vector<verify::PlannedPoint> wall(int layers) {
  std::vector<verify::PlannedPoint> out;
  for (int k = 0; k < layers; ++k) {
    const double z = 0.3 + 0.6 * k;
    out.push_back({{20.0, -10.0, z}, false});
    out.push_back({{20.0, 10.0, z}, true});
  }
  return out;
}

TEST(LayerTravel, AStraightTravelThroughTheWallGoesOverItAndOneBesideItStaysStraight) {
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const machine::BuildModel model = machine::make_build_model(m, p, -40, -40, 40, 40);
  // Walls taller than the tip's own zone (verify::kIgnoreBeads), which the nozzle's cone meets, and
  // lower than the cylinder above the cone (20 mm up; it is 25 mm wide: over a taller wall 20 mm
  // away the head at the travel's start would already be in it).
  for (const int layers : {12, 30}) {
    const auto points = wall(layers);
    const verify::DepositCheck deposit(model, points, kBead);
    const Vec3 up{0, 0, 1};
    // From one side of the wall to the other, on the plate: the nozzle would cut through it.
    const Vec3 from{0.0, 0.0, 0.3}, to{40.0, 0.0, 0.3};
    const auto via = layer_travel(model, deposit, points.size(), 0.5, 0.5 * kBead, from, up, to, up);
    ASSERT_EQ(via.size(), 2u) << layers;
    // Out along the axis above the wall's top, across, and down.
    EXPECT_GT(via[0].tip.z, 0.3 + 0.6 * layers) << layers;
    EXPECT_DOUBLE_EQ(via[0].tip.z, via[1].tip.z);
    EXPECT_DOUBLE_EQ(via[0].tip.x, from.x);
    EXPECT_DOUBLE_EQ(via[1].tip.x, to.x);
    // Every 0.25 mm of the three legs clear of the wall.
    const Vec3 legs[] = {from, via[0].tip, via[1].tip, to};
    for (int leg = 0; leg < 3; ++leg) {
      const Vec3 a = legs[leg], b = legs[leg + 1];
      const int n = static_cast<int>(std::ceil(core::norm(b - a) / 0.25));
      for (int i = leg == 0 ? 1 : 0; i < (leg == 2 ? n : n + 1); ++i) {
        EXPECT_FALSE(deposit.strikes(a + (b - a) * (static_cast<double>(i) / n), up, points.size(), 0.0)) << layers << " leg " << leg << " " << i;
      }
    }
    // Parallel to the wall, 15 mm beside it: straight.
    EXPECT_TRUE(layer_travel(model, deposit, points.size(), 0.5, 0.5 * kBead, {0, -10, 0.3}, up, {0, 10, 0.3}, up).empty()) << layers;
    // Before the wall was laid (program point 0): straight through where it will stand.
    EXPECT_TRUE(layer_travel(model, deposit, 0, 0.5, 0.5 * kBead, from, up, to, up).empty()) << layers;
  }
}

// Two tips 65 mm over the plate, 40 mm out from the middle, built along axes 16° below the
// horizon 135° apart in azimuth (blades on a flaring hub): leaving along the axis runs the head's
// cylinder down into the table on the way to the transit sphere, so the legs out and in turn up
// until clear; every sample of the first two moves and the last two keeps the head over it.
TEST(ClearTravel, LegsAlongAxesBelowTheHorizonTurnUpUntilTheHeadClearsTheTable) {
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const machine::BuildModel model = machine::make_build_model(m, p, -30, -30, 30, 30);
  const verify::DepositCheck deposit(model, {}, kBead);
  const double lat = -16.0 * kDeg;
  for (const double apart_deg : {135.0, 60.0}) {
    SCOPED_TRACE(apart_deg);
    const double h = 0.5 * apart_deg * kDeg;
    const Vec3 a{std::cos(lat) * std::cos(-h), std::cos(lat) * std::sin(-h), std::sin(lat)};
    const Vec3 b{std::cos(lat) * std::cos(h), std::cos(lat) * std::sin(h), std::sin(lat)};
    const Vec3 from = Vec3{40 * std::cos(-h), 40 * std::sin(-h), 65}, to = Vec3{40 * std::cos(h), 40 * std::sin(h), 65};
    ASSERT_GT(machine::head_clearance_mm(model, from, a), 0.5);  // the ends themselves are clear
    ASSERT_GT(machine::head_clearance_mm(model, to, b), 0.5);
    const auto via = clear_travel(model, deposit, 0, 0.5, 0.5 * kBead, from, a, to, b, {0, 0, 40}, 90.0);
    ASSERT_GE(via.size(), 2u);
    std::vector<TransitPoint> path{{from, a}};
    path.insert(path.end(), via.begin(), via.end());
    path.push_back({to, b});
    for (const std::size_t k : {std::size_t{0}, std::size_t{1}, path.size() - 3, path.size() - 2}) {
      for (int i = 0; i <= 50; ++i) {
        const double u = i / 50.0;
        const Vec3 tip = path[k].tip + (path[k + 1].tip - path[k].tip) * u;
        const Vec3 axis = core::normalized(path[k].axis * (1.0 - u) + path[k + 1].axis * u);
        EXPECT_GE(machine::head_clearance_mm(model, tip, axis), 0.5 - 1e-6) << "move " << k << " at " << u;
      }
    }
  }
}

// A travel between two fins on a hub, both axes below the horizon, 72° apart: the post moves the
// tip straight and turns the axis evenly in angle, which puts the far end of the head's cylinder
// 0.2 mm into the table a fifth of the way along; an even fraction of the chord between the axes,
// which the planner's check once sampled, kept it 0.7 mm over. The check follows the post: the
// travel is not taken straight, and the way it takes keeps the head over the table.
TEST(ClearTravel, AStraightTravelIsCheckedAsThePostTurnsTheAxis) {
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const machine::BuildModel model = machine::make_build_model(m, p, -25.456, -19.793, 18.544, 24.207);
  const verify::DepositCheck deposit(model, {}, kBead);
  const Vec3 from{34.21, -2.81, 28.93}, a = core::normalized({0.99, -0.12, -0.079});
  const Vec3 to{14.11, 42.97, 60.58}, b = core::normalized({0.413, 0.889, -0.196});
  double straight = INFINITY;
  for (int i = 0; i <= 100; ++i) {
    const double u = i / 100.0;
    straight = std::min(straight, machine::head_clearance_mm(model, from + (to - from) * u, axis_between(a, b, u)));
  }
  ASSERT_LT(straight, 0.0);  // the premise: straight, the post's move strikes the table
  const auto via = clear_travel(model, deposit, 0, 0.5, 0.5 * kBead, from, a, to, b, {0, 0, 40}, 120.0);
  ASSERT_FALSE(via.empty());
  if (via.size() == 2) {  // out, across and in: every sample as the post writes each move
    const TransitPoint legs[] = {{from, a}, via[0], via[1], {to, b}};
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i <= 100; ++i) {
        const double u = i / 100.0;
        const Vec3 tip = legs[k].tip + (legs[k + 1].tip - legs[k].tip) * u;
        EXPECT_GE(machine::head_clearance_mm(model, tip, axis_between(legs[k].axis, legs[k + 1].axis, u)), 0.5 - 1e-6) << k << " " << u;
      }
    }
  }
}

// A mushroom: a stem (R_STEM) under a cap spreading out at OVERHANG_DEG from vertical, both
// revolved; the cap's perimeters are laid with the torch tilted over the overhang and its fill
// along the layer's normal, so the head turns back from the tilt on the fill's first move.
io::RawMesh mushroom(double r_stem, double overhang_deg, double cap_h) {
  const double spread = cap_h * std::tan(overhang_deg * std::numbers::pi / 180.0);
  return test::revolve({{r_stem, 0.0}, {r_stem, 8.0}, {r_stem + spread, 8.0 + cap_h}, {r_stem + spread, 10.0 + cap_h}}, 96);
}

TEST(EaseTilts, ThePlansOwnChecksLeaveTheReadBackNothingToRelieve) {
  // Parts of my own with tilted torches over overhangs, at several sizes and angles, and a
  // decomposed one: every plan reads back clean the first time (no relief round), which needs the
  // move from a tilted point to one along the normal (the head turning back) checked, and the
  // travel between paths routed around the layer's deposit.
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  struct Case {
    io::RawMesh part;
    Strategy strategy;
  };
  const std::vector<Case> cases{{mushroom(6.0, 40.0, 10.0), Strategy::kSingle},
                                {mushroom(10.0, 50.0, 8.0), Strategy::kSingle},
                                {mushroom(4.0, 55.0, 6.0), Strategy::kSingle},
                                // An L whose arm juts out sideways at the top: decomposed.
                                {test::prism_xz({{0, 0}, {10, 0}, {10, 14}, {30, 14}, {30, 20}, {0, 20}}, 16.0), Strategy::kDecompose}};
  for (std::size_t k = 0; k < cases.size(); ++k) {
    PlanPartOptions o;
    o.strategy = cases[k].strategy;
    auto r = plan_part(test::repaired(cases[k].part), m, p, o);
    ASSERT_TRUE(r.ok()) << k << ": " << r.error().message;
    EXPECT_EQ(r.value().plan.relief_rounds, 0u) << k;
    EXPECT_EQ(r.value().check.collisions, 0u) << k;
    if (cases[k].strategy == Strategy::kSingle) {
      EXPECT_GT(r.value().plan.max_tilt_deg, 5.0) << k;  // the torch did tilt
    }
  }
}


// High enough over the plate that the head tilted 60° keeps clear of it (the cylinder's rim dips
// 21.7 mm below its centre, 10 mm above the tip).
constexpr double kLayerZ = 40.0;

// One layer along +Z at Z = kLayerZ with a bead laid first at BEAD, then a path P0 → P1 → P2: P0 20 mm
// along −Y with the torch along the normal, P1 with the torch tilted 60° towards +X, P2 3 mm back
// along −X with the torch along the normal again.
Plan turning_back_plan(const machine::MachineConfig& m, const process::ProcessConfig& p, Vec3 bead) {
  Plan plan;
  plan.build_model = machine::make_build_model(m, p, -40, -40, 40, 40);
  slicing::Layer layer;
  layer.frame = slicing::plane_frame({0, 0, 1}, kLayerZ);
  plan.layers.layers = {layer};
  plan.region_of_layer = {0};
  plan.placed_regions.resize(1);
  const Vec3 up{0, 0, 1}, tilted{std::sin(60.0 * kDeg), 0.0, std::cos(60.0 * kDeg)};
  const Vec3 p1{0.0, 0.0, kLayerZ};
  toolpath::LayerToolpaths lt;
  toolpath::Path laid, path;
  laid.kind = path.kind = toolpath::PathKind::kFill;
  laid.points = {{bead, up, false}, {bead + Vec3{0.0, 0.6, 0.0}, up, true}};
  path.points = {{p1 - Vec3{0.0, 20.0, 0.0}, up, false}, {p1, tilted, true}, {p1 - Vec3{3.0, 0.0, 0.0}, up, true}};
  lt.paths = {laid, path};
  plan.toolpaths = {lt};
  return plan;
}

TEST(EaseTilts, TheHeadTurningBackFromATiltToTheNormalIsCheckedAndTheTiltEased) {
  // A bead 12 mm from P1 in a direction 28° from the middle of the turn from P1's tilt (60° towards
  // +X) to the normal, off to the side (+Y): 40° from either end (clear of the 30° cone with its
  // margins), inside the cone half way. Moving from P1 to P2 (3 mm, turning 60°: in place where the
  // rotary axes cannot keep up) the head sweeps through the bead. P2 lies along the normal, where a
  // planar layer's own deposit is never struck; the move into it is checked all the same, and, P2
  // having nowhere to turn, P1's tilt is eased towards the normal until the move clears.
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const Vec3 mid{std::sin(30.0 * kDeg), 0.0, std::cos(30.0 * kDeg)}, side{0, 1, 0};
  const Vec3 u = mid * std::cos(28.0 * kDeg) + side * std::sin(28.0 * kDeg);
  const Vec3 bead = Vec3{0.0, 0.0, kLayerZ} + u * 12.0;
  Plan plan = turning_back_plan(m, p, bead);
  const verify::DepositCheck deposit(plan.build_model, planned_points(plan), p.bead_width_mm);
  const std::size_t p1 = 3, p2 = 4;  // flat indices: the bead's two points, then P0, P1, P2
  const Vec3 up{0, 0, 1};
  const toolpath::Path& path = plan.toolpaths[0].paths[1];
  // As planned: P1 and P2 each clear; the torch at P1 half way to the normal strikes the bead.
  EXPECT_FALSE(deposit.strikes(path.points[1].position_mm, path.points[1].tool_axis, p1, 0.0));
  EXPECT_FALSE(deposit.strikes(path.points[2].position_mm, up, p2, 0.0));
  EXPECT_TRUE(deposit.strikes(path.points[1].position_mm, mid, p2, 0.0));
  PlanOptions o;
  ease_tilts(plan, m, o, deposit, p.bead_width_mm, p.deposit_feed_mm_s);
  EXPECT_GE(plan.tilts_eased, 1u);
  // Every axis on the way from P1's (eased) axis to the normal, at P1 and along the move: clear.
  const toolpath::Path& eased = plan.toolpaths[0].paths[1];
  const Vec3 a = core::normalized(eased.points[1].tool_axis), t1 = eased.points[1].position_mm, t2 = eased.points[2].position_mm;
  EXPECT_LT(std::acos(std::clamp(core::dot(a, up), -1.0, 1.0)), 60.0 * kDeg - 1e-6);
  for (int k = 0; k <= 60; ++k) {
    const double w = k / 60.0;
    const Vec3 axis = core::normalized(a * (1.0 - w) + up * w);
    EXPECT_FALSE(deposit.strikes(t1, axis, p2, 0.0)) << "in place " << w;
    EXPECT_FALSE(deposit.strikes(t1 + (t2 - t1) * w, axis, p2, 0.0)) << "on the way " << w;
  }
}


TEST(EaseTilts, APathsFirstPointIsEasedAndTheTravelIntoItTakesTheEasedAxis) {
  // A bead laid first 12 mm out along the torch at P1, the first point of a path after a travel,
  // tilted 60° towards +X: the head there strikes it. The travel into P1 is routed by the program
  // (layer_travel), so P1 is checked alone and eased towards the normal, and the travel arrives
  // with P1's eased axis. Before, the travel's end (a copy of P1 as planned) was eased on its own,
  // here to another axis than P1's, and the program turned the torch in place at the path's start,
  // a turn no check had seen (the tuning fork decomposed on planar layers struck an arm so).
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const Vec3 up{0, 0, 1}, tilted{std::sin(60.0 * kDeg), 0.0, std::cos(60.0 * kDeg)};
  const Vec3 p1{0.0, 0.0, kLayerZ};
  const Vec3 bead = p1 + tilted * 12.0;
  Plan plan = turning_back_plan(m, p, bead);
  toolpath::LayerToolpaths& lt = plan.toolpaths[0];
  toolpath::Path path;
  path.kind = toolpath::PathKind::kPerimeter;
  path.points = {{p1, tilted, false}, {p1 - Vec3{3.0, 0.0, 0.0}, tilted, true}, {p1 - Vec3{6.0, 0.0, 0.0}, tilted, true}};
  toolpath::Path travel;
  travel.kind = toolpath::PathKind::kTravel;
  travel.points = {lt.paths[0].points.back(), {p1, tilted, false}};
  travel.points.back().deposit = false;
  lt.paths = {lt.paths[0], travel, path};
  const verify::DepositCheck deposit(plan.build_model, planned_points(plan), p.bead_width_mm);
  const std::size_t first = 4;  // flat index of P1: the bead's two points, the travel's two
  ASSERT_TRUE(deposit.strikes(p1, tilted, first, 0.0));
  PlanOptions o;
  ease_tilts(plan, m, o, deposit, p.bead_width_mm, p.deposit_feed_mm_s);
  const toolpath::Path& eased = plan.toolpaths[0].paths[2];
  const Vec3 a = core::normalized(eased.points[0].tool_axis);
  EXPECT_FALSE(deposit.strikes(p1, a, first, 0.0)) << a.x << " " << a.y << " " << a.z;
  EXPECT_LT(std::acos(std::clamp(core::dot(a, up), -1.0, 1.0)), 60.0 * kDeg - 1e-6);
  // The travel leaves with the bead's last axis and arrives with P1's, as eased.
  const toolpath::Path& t = plan.toolpaths[0].paths[1];
  EXPECT_EQ(t.points.front().tool_axis, plan.toolpaths[0].paths[0].points.back().tool_axis);
  EXPECT_EQ(t.points.back().tool_axis, eased.points[0].tool_axis);
}

TEST(EaseTilts, WhereTheWriterTurnsTheTorchInPlaceTheTurnsEndIsChecked) {
  // P0 along the normal, then a deposit move of 0.8 mm along −X to P1, tilted 45° towards +X: the
  // rotary axes cannot turn so far over so short a bead, and the writer turns the torch in place
  // at P0 with the process off, then lays the bead at P1's axis (post::splits_stall). A bead laid
  // first just inside the head's reach at (P0, P1's axis), beyond the tilt (the turn meets it only
  // at its end) and out of reach at P1: the move's samples, the turn's inside and P1 itself are
  // clear, only the bead's start is not. Before, that pose was checked by nothing, and bumpy_82k's
  // first program struck the layer below there, 0.2 mm deep (a relief round cleared it).
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const double margin = kDepositMarginBeads * p.bead_width_mm;
  const Vec3 up{0, 0, 1}, tilted{std::sin(45.0 * kDeg), 0.0, std::cos(45.0 * kDeg)};
  const Vec3 p0{0.0, 0.0, kLayerZ}, p1 = p0 - Vec3{0.8, 0.0, 0.0};
  ASSERT_TRUE(post::splits_stall(m, p0, up, p1, tilted, p.deposit_feed_mm_s));
  // The bead 10 mm from P0 in the tilt's plane, BETA further from the normal than P1's axis.
  auto plan_with_bead_at = [&](double beta_deg) {
    const double a = (45.0 + beta_deg) * kDeg;
    Plan plan = turning_back_plan(m, p, p0 + Vec3{std::sin(a), 0.0, std::cos(a)} * 10.0);
    toolpath::Path& path = plan.toolpaths[0].paths[1];
    path.points = {{p0, up, false}, {p1, tilted, true}};
    return plan;
  };
  const std::size_t first = 2, second = 3;  // flat indices of P0 and P1 after the bead's two points
  auto struck = [&](double beta_deg) {
    const Plan plan = plan_with_bead_at(beta_deg);
    const verify::DepositCheck deposit(plan.build_model, planned_points(plan), p.bead_width_mm);
    return deposit.strikes(p0, tilted, second, margin);
  };
  // The widest angle at which the head there reaches the bead, to 0.01°.
  double lo = 0.0, hi = 60.0;
  ASSERT_TRUE(struck(lo));
  ASSERT_FALSE(struck(hi));
  while (hi - lo > 0.01) (struck(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  Plan plan = plan_with_bead_at(lo - 0.3);
  const verify::DepositCheck deposit(plan.build_model, planned_points(plan), p.bead_width_mm);
  ASSERT_TRUE(deposit.strikes(p0, tilted, second, margin));
  EXPECT_FALSE(deposit.strikes(p0, up, first, margin));
  EXPECT_FALSE(deposit.strikes(p1, tilted, second, margin));
  for (int k = 1; k < 45; ++k) {  // the turn at P0, a degree apart, short of its end
    const double w = k * kDeg;
    EXPECT_FALSE(deposit.strikes(p0, up * std::cos(w) + Vec3{1, 0, 0} * std::sin(w), second, margin)) << k;
  }
  PlanOptions o;
  ease_tilts(plan, m, o, deposit, p.bead_width_mm, p.deposit_feed_mm_s);
  const Vec3 a = core::normalized(plan.toolpaths[0].paths[1].points[1].tool_axis);
  EXPECT_GE(plan.tilts_eased, 1u);
  EXPECT_LT(std::acos(std::clamp(core::dot(a, up), -1.0, 1.0)), 45.0 * kDeg - 1e-6);
  EXPECT_FALSE(deposit.strikes(p0, a, second, margin)) << a.x << " " << a.y << " " << a.z;
}

}  // namespace
}  // namespace polyaxis::planner::detail
