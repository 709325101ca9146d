// Issue 13's impeller (examples/parts/impeller.stl: a hub flaring from r 28 to 50 over 75 mm with
// eight twisted blades 3 mm thick at the root, their outer edge leaning 41° out) built onto its hub
// on conformal layers, judged from the G-code alone: `plan --substrate HUB --strategy decompose
// --layers conformal`, the hub made here as impeller.scad makes it and stood on a shaft so that the
// blades clear the plate. Every blade is a region of its own on conformal layers; the plan is
// support-free; read back through forward kinematics every bead is grounded and the head strikes
// neither the hub, the table nor the deposit; the thickness at every deposit point, measured along
// its tool axis to the region's layer before (to the hub for the first), stays in the process's
// range; rs274 accepts the program. It took the gap fill between perimeters (the blades' ends
// crossed bare channels: 304 ungrounded samples) and the support check on the layer below rather
// than on the base (footprints folded at the hub's rim: 0.028 mm²).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/cli.h"
#include "support/mesh_union.h"
#include "support/meshes.h"
#include "support/plan_checks.h"

namespace polyaxis::test {
namespace {

TEST(PlanImpeller, BladesGrowOnConformalLayersFromTheirHubSupportFreeAndGrounded) {
  auto process = process::parse_process(process::default_process_json(), "default");
  ASSERT_TRUE(process.ok());
  const process::ProcessConfig& p = process.value();
  TempDir dir;
  const RawMesh hub = mesh_union(frustum(28, 50, 75, 128), cylinder({0, 0, -40}, {0, 0, 1}, 20, 40.5, 64));
  write_file(dir / "hub.stl", binary_stl(hub));
  const std::string part = std::string(POLYAXIS_PARTS_DIR) + "/impeller.stl";
  const auto r = run_cli(fmt::format("plan '{}' --substrate '{}' --strategy decompose --layers conformal --no-html -o '{}'", part,
                                     (dir / "hub.stl").string(), dir.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_json(dir / "report.json");
  EXPECT_TRUE(report["support_free"].get<bool>()) << report["unsupported_area_mm2"];
  EXPECT_EQ(report["unsupported_area_mm2"].get<double>(), 0.0);
  const auto plan = read_json(dir / "plan.json");
  ASSERT_EQ(plan["regions"].size(), 9u);  // the hub and eight blades
  for (std::size_t k = 1; k < plan["regions"].size(); ++k) {
    EXPECT_EQ(plan["regions"][k]["layers"]["strategy"], "conformal") << "region " << k;
    // Along the hub's normal, 16° below the horizon (placed about Z only).
    EXPECT_NEAR(std::asin(plan["regions"][k]["build_direction"][2].get<double>()), -std::atan2(22.0, 75.0), 2.0 * M_PI / 180.0) << "region " << k;
  }
  const RawMesh on_table = placed(hub, plan);
  const ReadBack rb = check_readback(dir.path(), "impeller", false, &on_table);
  EXPECT_EQ(rb.ungrounded, 0u) << rb.first_problem;
  expect_rs274_reads(dir.path(), dir / "impeller.ngc");
  const Thickness th = bead_thickness(deposit_tips(dir.path(), "impeller"), on_table, p.bead_width_mm);
  const double tol = 0.05;  // the hub's faceting and the beads' spacing across the axis
  EXPECT_GE(th.least, p.layer_min_mm - tol);
  EXPECT_LE(th.most, p.layer_max_mm + tol);
  EXPECT_GT(th.measured, th.points / 2) << th.measured << " of " << th.points;
}

}  // namespace
}  // namespace polyaxis::test
