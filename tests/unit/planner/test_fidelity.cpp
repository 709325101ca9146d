// Fidelity figures (issue 13, item 6; SPEC §3): the largest cusp height and the symmetric
// difference between the deposited layers and the part, on parts whose answer is known.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>

#include "polyaxis/machine/machine.h"
#include "polyaxis/planner/plan.h"
#include "polyaxis/process/process.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::planner {
namespace {

using polyaxis::test::repaired;

struct Configs {
  machine::MachineConfig machine;
  process::ProcessConfig process;
};

Configs defaults() {
  auto m = machine::parse_machine(machine::default_machine_json(), "default");
  auto p = process::parse_process(process::default_process_json(), "default");
  EXPECT_TRUE(m.ok() && p.ok());
  return {m.value(), p.value()};
}

Plan planned(const mesh::RepairedMesh& part, const process::ProcessConfig& process, LayerChoice layers = LayerChoice::kPlanar) {
  const Configs s = defaults();
  PlanOptions o;
  o.layers = layers;
  auto plan = make_plan(part, s.machine, process, o);
  EXPECT_TRUE(plan.ok()) << (plan.ok() ? "" : plan.error().message);
  return std::move(plan.value());
}

// PlanOptions::stop: set, make_plan ends at its first stage with kInfeasible "stopped"; unset, the
// same call plans the part. (Fidelity's plans are the nearest ready-made calls.)
TEST(MakePlan, AStopSetEndsThePlanAtItsNextStage) {
  const Configs s = defaults();
  const mesh::RepairedMesh part = repaired(test::box({0, 0, 0}, {20, 14, 9}));
  std::atomic<bool> stop{true};
  PlanOptions o;
  o.layers = LayerChoice::kPlanar;
  o.stop = &stop;
  auto stopped = make_plan(part, s.machine, s.process, o);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().code, core::ErrorCode::kInfeasible);
  EXPECT_EQ(stopped.error().message, "stopped");
  stop = false;
  auto plan = make_plan(part, s.machine, s.process, o);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  EXPECT_FALSE(plan.value().program.empty());
}

// Walls along the build direction and flat ends: no staircase and nothing gained or lost, at any
// size and layer thickness.
TEST(Fidelity, APrismAlongTheBuildDirectionIsReproducedExactly) {
  for (const auto& [lo, hi] : {std::pair<core::Vec3, core::Vec3>{{0, 0, 0}, {20, 14, 9}}, {{-3, 5, 0}, {4, 40, 23.5}}}) {
    const Plan plan = planned(repaired(test::box(lo, hi)), defaults().process);
    EXPECT_EQ(plan.fidelity.max_cusp_mm, 0.0);
    EXPECT_LT(plan.fidelity.volume_difference_share, 1e-6);
  }
}

// A cone's side leans: every layer leaves a staircase, its height t·|n·d| for the side's normal n.
TEST(Fidelity, AConeLeavesAStaircaseThatThinnerLayersShrink) {
  Configs s = defaults();
  s.process.adaptive_layers = false;
  const mesh::RepairedMesh cone = repaired(test::frustum(20, 8, 24, 96));
  const double n_dot_d = std::sin(std::atan((20.0 - 8.0) / 24.0));  // the side's normal against +Z
  const Plan thick = planned(cone, s.process);
  EXPECT_NEAR(thick.fidelity.max_cusp_mm, s.process.layer_mm * n_dot_d, 1e-3);  // a 96-gon: the facets lean a little less
  EXPECT_GT(thick.fidelity.volume_difference_share, 0.0);
  s.process.layer_mm = s.process.layer_min_mm;
  const Plan thin = planned(cone, s.process);
  EXPECT_NEAR(thin.fidelity.max_cusp_mm, s.process.layer_min_mm * n_dot_d, 1e-3);
  EXPECT_LT(thin.fidelity.volume_difference_share, 0.75 * thick.fidelity.volume_difference_share);
  // The error band of a frustum sliced at t: about the side's area times t·|n·d|/4 (each half of a
  // layer misses a wedge of mean depth t/4·tan of the lean); the figure is of that order.
  const double side = std::numbers::pi * (20.0 + 8.0) * std::hypot(12.0, 24.0);
  const double band = side * s.process.layer_min_mm * n_dot_d / 4.0;
  EXPECT_NEAR(thin.fidelity.volume_difference_mm3, band, 0.5 * band);
}

// A bent bar on layers that follow it leaves less staircase than on planar layers.
TEST(Fidelity, TiltedLayersFollowingABentBarReproduceItMoreClosely) {
  const mesh::RepairedMesh bar = repaired(test::bent_bar(60, 6, 70, 40, 24));
  const Plan planar = planned(bar, defaults().process, LayerChoice::kPlanar);
  const Plan tilted = planned(bar, defaults().process, LayerChoice::kTilted);
  EXPECT_LT(tilted.fidelity.volume_difference_share, planar.fidelity.volume_difference_share);
  EXPECT_GT(tilted.fidelity.volume_difference_share, 0.0);
}

}  // namespace
}  // namespace polyaxis::planner
