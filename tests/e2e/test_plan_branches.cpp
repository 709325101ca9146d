// Branches grown on their trunk (plan_part's trunk splits, issue 13): a part whose branch leaves
// its trunk sideways, which no planar decomposition holds, plans support-free with defaults: the
// trunk first, each branch on conformal layers from the trunk's surface. Judged from the G-code
// read back (support/plan_checks.h): every bead grounded, the head clear, no region in mid-air, the
// thickness along the tool axis in the process's range, rs274 accepting the program. The parts:
// two_branches (Ruan Fig. 11) and parts of our own (tests/corpus/branches): a column with three
// arms round its side, a Y fork, a tuning fork, a column with one arm, and two_branches at other
// sizes, and columns on a round foot.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "support/cli.h"
#include "support/meshes.h"
#include "support/plan_checks.h"

namespace polyaxis::test {
namespace {


// Plans DIR/NAME.stl with defaults and checks it grew its branches on its trunk, support-free and
// sound as read back. ERR: the run's stderr, when given.
void expect_grown_on_trunk(const TempDir& dir, const std::string& name, std::string* err = nullptr) {
  const auto r = run_cli(fmt::format("plan '{}' --no-html -o '{}'", (dir.path() / (name + ".stl")).string(), dir.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  if (err != nullptr) *err = r.err;
  const auto report = read_json(dir.path() / "report.json");
  EXPECT_TRUE(report["support_free"].get<bool>()) << report["strategy_reason"];
  EXPECT_NE(report["strategy_reason"].get<std::string>().find("grown on the trunk"), std::string::npos) << report["strategy_reason"];
  const auto plan = read_json(dir.path() / "plan.json");
  std::set<std::string> rules;
  for (const auto& region : plan["regions"]) {
    rules.insert(region["rule"].get<std::string>());
    // The branches follow the trunk's surface; the trunk is one region (or its own decomposition).
    if (region["rule"] == "branch on its trunk") {
      EXPECT_EQ(region["layers"]["strategy"], "conformal") << region["id"];
    }
  }
  EXPECT_TRUE(rules.count("branch on its trunk"));
  check_readback(dir.path(), name);
  expect_rs274_reads(dir.path(), dir.path() / (name + ".ngc"));
  // The thickness along each deposit point's tool axis, measured from the beads of the layer before
  // (the first layer of a branch from the trunk's beads, not measured), stays in the process's range.
  auto process = process::parse_process(process::default_process_json(), "default");
  ASSERT_TRUE(process.ok());
  const process::ProcessConfig& p = process.value();
  const Thickness th = bead_thickness(deposit_tips(dir.path(), name), io::RawMesh{}, p.bead_width_mm);
  const double tol = 0.05;  // the beads' spacing across the axis
  EXPECT_GE(th.least, p.layer_min_mm - tol);
  EXPECT_LE(th.most, p.layer_max_mm + tol);
  EXPECT_GT(th.measured, th.points / 2) << th.measured << " of " << th.points;
}

// tests/corpus/branches/NAME.stl copied into DIR and checked as expect_grown_on_trunk does.
void expect_corpus_part_grown_on_trunk(const TempDir& dir, const std::string& name) {
  std::filesystem::copy_file(std::string(POLYAXIS_CORPUS_DIR) + "/branches/" + name + ".stl", dir.path() / (name + ".stl"));
  expect_grown_on_trunk(dir, name);
}

TEST(PlanBranches, TwoBranchesGrowsItsHangingArmOnTheOtherSupportFreeByDefault) {
  TempDir dir;
  std::filesystem::copy_file(std::string(POLYAXIS_PARTS_DIR) + "/two_branches.stl", dir.path() / "two_branches.stl");
  expect_grown_on_trunk(dir, "two_branches");
  // The trunk is the column and the −X arm; the +X arm, less the tube round the −X arm, the branch.
  const auto plan = read_json(dir.path() / "plan.json");
  ASSERT_EQ(plan["regions"].size(), 2u);
  EXPECT_EQ(plan["regions"][1]["rule"], "branch on its trunk");
  EXPECT_GT(plan["regions"][1]["build_direction"][0].get<double>(), 0.5);  // grown out along +X
}

TEST(PlanBranches, AColumnWithThreeArmsRoundItsSideGrowsThemOnTheColumn) {
  TempDir dir;
  expect_corpus_part_grown_on_trunk(dir, "three_arms");
}

// three_arms on a round foot: the foot's flat disc puts spurs into the skeleton that no round tube
// holds, so the trunk's tubes leave them out and the foot goes back to the trunk (before, every
// trunk split was refused as not round, and the planar decomposition left 0.5 mm² overhanging).
TEST(PlanBranches, AColumnWithArmsStandingOnARoundFootGrowsThemOnTheColumn) {
  TempDir dir;
  expect_corpus_part_grown_on_trunk(dir, "footed_arms");
  // The trunk holds the foot: it stands on the plate and holds more than the foot's volume.
  const auto plan = read_json(dir.path() / "plan.json");
  ASSERT_GE(plan["regions"].size(), 2u);
  EXPECT_EQ(plan["regions"][0]["rule"], "trunk");
  EXPECT_GT(plan["regions"][0]["volume_mm3"].get<double>(), std::numbers::pi * 14.0 * 14.0 * 4.0);
}

// A column on a round foot with arms at two heights and azimuths.
TEST(PlanBranches, AColumnOnAFootWithArmsAtTwoHeightsGrowsThemOnTheColumn) {
  TempDir dir;
  expect_corpus_part_grown_on_trunk(dir, "two_heights");
}

// A Y fork and a tuning fork of our own: both arms leave the column at an angle and stand close.
// Grown one on the other, the head building the second strikes the first (read back); both grown
// on the column, the trunk ending at the fork, they are support-free.
void expect_both_arms_on_the_column(const std::string& name, std::string* err = nullptr) {
  TempDir dir;
  std::filesystem::copy_file(std::string(POLYAXIS_CORPUS_DIR) + "/branches/" + name + ".stl", dir.path() / (name + ".stl"));
  expect_grown_on_trunk(dir, name, err);
  const auto report = read_json(dir.path() / "report.json");
  EXPECT_EQ(report["strategy_reason"].get<std::string>().rfind("the 2 branches leaving", 0), 0u) << report["strategy_reason"];
  const auto plan = read_json(dir.path() / "plan.json");
  ASSERT_EQ(plan["regions"].size(), 2u);
  EXPECT_EQ(plan["regions"][0]["rule"], "trunk");
}

TEST(PlanBranches, AYForkGrowsBothArmsOnItsColumn) { expect_both_arms_on_the_column("yfork"); }

// The fork's arms leave the handle's top sideways and the torch follows their conformal layers
// round the joint faster than the rotary axes turn: the writer turns it in place with the process
// off thousands of times, and the plan says so (the restarts' dwells are 46 % of the build).
TEST(PlanBranches, ATuningForkGrowsBothArmsOnItsHandle) {
  std::string err;
  expect_both_arms_on_the_column("tuning_fork", &err);
  EXPECT_NE(err.find("warning: the process is switched off and on again"), std::string::npos) << err;
}

// A column with one arm leaving its side: its trunk splits overhang a little (0.1 mm²), and so does
// each candidate on the layers auto judged best region by region; the same choice on planar layers
// holds it with two regions, support-free. Auto compares the two whenever its plan overhangs.
TEST(PlanBranches, AColumnWithOneArmTakesThePlanarDecompositionThatHoldsIt) {
  TempDir dir;
  std::filesystem::copy_file(std::string(POLYAXIS_CORPUS_DIR) + "/branches/side_arm.stl", dir.path() / "side_arm.stl");
  const auto r = run_cli(fmt::format("plan '{}' --no-html -o '{}'", (dir.path() / "side_arm.stl").string(), dir.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_json(dir.path() / "report.json");
  EXPECT_TRUE(report["support_free"].get<bool>()) << report["strategy_reason"];
  check_readback(dir.path(), "side_arm");
}

// two_branches at other sizes: the trunk and branch leave far less overhang than the planar
// decomposition (6.7 mm² there), though not none (the conformal layers' last ones at the arm's end
// face), and the program reads back sound.
TEST(PlanBranches, TwoBranchesAtOtherSizesOverhangsLessOnItsTrunk) {
  TempDir dir;
  std::filesystem::copy_file(std::string(POLYAXIS_CORPUS_DIR) + "/branches/branches_r35.stl", dir.path() / "branches_r35.stl");
  const auto trunk = run_cli(fmt::format("plan '{}' --no-html -o '{}'", (dir.path() / "branches_r35.stl").string(), (dir.path() / "auto").string()));
  ASSERT_EQ(trunk.exit_code, 0) << trunk.err;
  const auto split = run_cli(fmt::format("plan '{}' --strategy decompose --no-html -o '{}'", (dir.path() / "branches_r35.stl").string(),
                                         (dir.path() / "planes").string()));
  ASSERT_EQ(split.exit_code, 0) << split.err;
  const auto report = read_json(dir.path() / "auto" / "report.json"), planes = read_json(dir.path() / "planes" / "report.json");
  EXPECT_NE(report["strategy_reason"].get<std::string>().find("grown on the trunk"), std::string::npos) << report["strategy_reason"];
  EXPECT_LT(report["unsupported_area_mm2"].get<double>(), 0.5 * planes["unsupported_area_mm2"].get<double>());
  std::filesystem::copy_file(dir.path() / "branches_r35.stl", dir.path() / "auto" / "branches_r35.stl");
  check_readback(dir.path() / "auto", "branches_r35");
}

}  // namespace
}  // namespace polyaxis::test
