// The plan's support check: a layer rests on the layer below it and on the regions built before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "planner/support.h"

#include "polyaxis/mesh/repair.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/planner/plan.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::planner {
namespace {

constexpr double kPi = 3.14159265358979323846;

using polyaxis::test::repaired;

PlanRegion region(std::uint32_t id, const mesh::RepairedMesh& m, Vec3 direction, std::optional<std::uint32_t> parent) {
  PlanRegion r;
  r.id = id;
  r.mesh = m.mesh;
  r.direction = direction;
  r.parent = parent;
  return r;
}

// A 20 mm cube split at z = 10: the lower half built +Z, the upper half leaning 20° about Y (its
// layers start at one edge of the cut and spread over it, 2.7 mm a layer).
struct Split {
  mesh::RepairedMesh whole = repaired(polyaxis::test::box({0, 0, 0}, {20, 20, 20}));
  mesh::RepairedMesh lower = repaired(polyaxis::test::box({0, 0, 0}, {20, 20, 10}));
  mesh::RepairedMesh upper = repaired(polyaxis::test::box({0, 0, 10}, {20, 20, 20}));
  Vec3 leaning{std::sin(20.0 * kPi / 180.0), 0.0, std::cos(20.0 * kPi / 180.0)};
};

Plan plan_of(const mesh::RepairedMesh& whole, const std::vector<PlanRegion>& regions) {
  auto machine = machine::parse_machine(machine::default_machine_json(), "default");
  auto process = process::parse_process(process::default_process_json(), "default");
  EXPECT_TRUE(machine.ok() && process.ok());
  PlanOptions o;
  o.tilt_on_overhang = false;
  auto plan = make_plan(whole, machine.value(), process.value(), o, regions);
  EXPECT_TRUE(plan.ok()) << (plan.ok() ? "" : plan.error().message);
  return std::move(plan.value());
}

TEST(SupportCheck, LayersSpreadingOverTheRegionBelowRestOnIt) {
  const Split s;
  const Plan plan = plan_of(s.whole, {region(0, s.lower, {0, 0, 1}, std::nullopt), region(1, s.upper, s.leaning, 0)});
  EXPECT_EQ(plan.unsupported_area_mm2, 0.0);
  for (const PlanRegion& r : plan.placed_regions) EXPECT_TRUE(r.support_free) << r.id;
  // The upper region's layers do spread: each of its first layers reaches beyond the one before
  // by more than t·tan(α), which only the lower region holds up.
  std::size_t upper_layers = 0;
  double first_area = 0.0, tenth_area = 0.0;
  for (std::size_t k = 0; k < plan.layer_reports.size(); ++k) {
    if (plan.layer_reports[k].region != 1) continue;
    if (upper_layers == 0) first_area = plan.layer_reports[k].area_mm2;
    if (upper_layers == 9) tenth_area = plan.layer_reports[k].area_mm2;
    ++upper_layers;
  }
  EXPECT_GT(tenth_area, first_area + 100.0);
}

TEST(SupportCheck, ARegionBuiltBeforeWhatHoldsItIsRefused) {
  // The same regions the wrong way round: the upper half first stands on the plate, so the lower
  // half would have to go into the plate under it. Refused before slicing, naming the region.
  const Split s;
  auto machine = machine::parse_machine(machine::default_machine_json(), "default");
  auto process = process::parse_process(process::default_process_json(), "default");
  ASSERT_TRUE(machine.ok() && process.ok());
  auto plan = make_plan(s.whole, machine.value(), process.value(), PlanOptions{},
                        {region(0, s.upper, s.leaning, std::nullopt), region(1, s.lower, {0, 0, 1}, 0)});
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.error().code, core::ErrorCode::kInfeasible);
  EXPECT_NE(plan.error().message.find("region 1"), std::string::npos) << plan.error().message;
  EXPECT_NE(plan.error().message.find("below the substrate"), std::string::npos) << plan.error().message;
}

TEST(SupportCheck, ARegionsFirstLayerOverNothingHangs) {
  // A second region beside the first, 10 mm above the table: its first layer rests on nothing
  // built (before, a region's first layer was taken to rest on its parent unchecked).
  const mesh::RepairedMesh lower = repaired(polyaxis::test::box({0, 0, 0}, {20, 20, 10}));
  const mesh::RepairedMesh beside = repaired(polyaxis::test::box({30, 0, 10}, {40, 20, 20}));
  const mesh::RepairedMesh whole = repaired(polyaxis::test::join(polyaxis::test::box({0, 0, 0}, {20, 20, 10}),
                                                                 polyaxis::test::box({30, 0, 10}, {40, 20, 20})));
  const Plan plan = plan_of(whole, {region(0, lower, {0, 0, 1}, std::nullopt), region(1, beside, {0, 0, 1}, 0)});
  const auto first = std::find_if(plan.layer_reports.begin(), plan.layer_reports.end(), [](const LayerReport& r) { return r.region == 1; });
  ASSERT_NE(first, plan.layer_reports.end());
  EXPECT_NEAR(first->unsupported_area_mm2, first->area_mm2, 1e-6);
  EXPECT_NEAR(first->area_mm2, 200.0, 1e-6);
  EXPECT_FALSE(plan.placed_regions[1].support_free);
  EXPECT_TRUE(plan.placed_regions[0].support_free);
}

TEST(SupportCheck, TheTiltedTorchStepIsBoundedByTheBead) {
  // α = 30°, a torch leaning 60° more: t·tan(90°) would be unbounded; the bead bounds it.
  const double t = 0.6, bead = 0.9, share = 0.5;
  EXPECT_DOUBLE_EQ(detail::tilted_step_mm(t, 90.0, 30.0, share * bead), share * bead);
  EXPECT_DOUBLE_EQ(detail::tilted_step_mm(t, 89.9, 30.0, share * bead), share * bead);
  // Untilted, the plain t·tan α, even when the bead would allow more.
  EXPECT_NEAR(detail::tilted_step_mm(t, 30.0, 30.0, share * bead), t * std::tan(kPi / 6.0), 1e-12);
  // Leaning a little: t·tan(α + θ) while below the bound.
  EXPECT_NEAR(detail::tilted_step_mm(0.3, 40.0, 30.0, share * bead), 0.3 * std::tan(40.0 * kPi / 180.0), 1e-12);
  // Every share up to 1 keeps it at most a bead.
  for (const double s : {0.1, 0.5, 1.0}) EXPECT_LE(detail::tilted_step_mm(0.7, 89.0, 30.0, s * bead), bead);
}

TEST(SupportCheck, ARoundBarBentThrough110DegreesIsNotSupportFreeOnPlanarLayers) {
  // Its end leans 110° from vertical: no torch tilt lets a planar layer overhang its layer below by
  // more than half a bead, so the outer bend hangs. Other bends and sizes: the same.
  auto machine = machine::parse_machine(machine::default_machine_json(), "default");
  auto process = process::parse_process(process::default_process_json(), "default");
  ASSERT_TRUE(machine.ok() && process.ok());
  PlanOptions planar;
  planar.layers = LayerChoice::kPlanar;
  PlanOptions tilted;
  tilted.layers = LayerChoice::kTilted;
  for (const auto& [bend, bar, sweep] : {std::tuple{30.0, 5.0, 110.0}, std::tuple{45.0, 8.0, 100.0}, std::tuple{25.0, 4.0, 130.0}}) {
    const mesh::RepairedMesh m = repaired(polyaxis::test::bent_bar(bend, bar, sweep, 48, 24));
    auto plan = make_plan(m, machine.value(), process.value(), planar);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    EXPECT_GT(plan.value().unsupported_area_mm2, 10.0) << bend << " " << bar << " " << sweep;
    EXPECT_GT(plan.value().max_tilt_deg, 30.0);  // the torch does tilt on the outer bend
    // Tilted layers follow the bar: the same support check finds nothing hanging (issue 13). The
    // far end faces down towards the plate: a slim nozzle (no cylinder) reaches it.
    machine::MachineConfig slim = machine.value();
    slim.nozzle.cylinder_radius_mm = 0.0, slim.nozzle.cylinder_height_mm = 0.0, slim.nozzle.cone_height_mm = 8.0;
    auto followed = make_plan(m, slim, process.value(), tilted);
    ASSERT_TRUE(followed.ok()) << followed.error().message;
    EXPECT_EQ(followed.value().unsupported_area_mm2, 0.0) << bend << " " << bar << " " << sweep;
    EXPECT_EQ(followed.value().placed_regions.front().layers, slicing::LayerStrategy::kTilted);
  }
  // Bent through 20° only, the lean stays within what the tilted torch allows.
  const mesh::RepairedMesh gentle = repaired(polyaxis::test::bent_bar(60.0, 5.0, 20.0, 48, 24));
  auto plan = make_plan(gentle, machine.value(), process.value(), planar);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  EXPECT_EQ(plan.value().unsupported_area_mm2, 0.0);
}

}  // namespace
}  // namespace polyaxis::planner

namespace polyaxis::planner {
namespace {

// A summary said "NOT support-free (unsupported 0.0 mm2)" for 0.011 mm² (issue 14).
TEST(AreaText, ANonZeroAreaNeverReadsZero) {
  EXPECT_EQ(area_text(0.0), "0.0");
  EXPECT_EQ(area_text(0.011), "0.011");
  EXPECT_EQ(area_text(0.00042), "0.00042");
  EXPECT_EQ(area_text(248.44), "248.4");
  EXPECT_EQ(area_text(0.1), "0.1");
}

}  // namespace
}  // namespace polyaxis::planner
