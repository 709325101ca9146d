// A robot cell (issue 15, item 2: examples/machines/robot_abb_positioner.json, an ABB IRB 2400 over
// a tilt-and-turn positioner, ABB RAPID): the positioner turns each point's tool axis up, the robot
// carries the torch, and the module is read back twice apart from the planner: by the tests'
// robtarget reader through the arm's own inverse and forward kinematics onto plan.json's program
// points, and by the build read-back (head above the plate, every bead grounded, no stalls).
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>

#include "polyaxis/report/plan_view.h"
#include "support/cli.h"
#include "support/meshes.h"
#include "support/plan_checks.h"
#include "support/rapid_replay.h"
#include "support/readback.h"

namespace polyaxis::test {
namespace {

std::filesystem::path robot_machine() {
  return std::filesystem::path(POLYAXIS_PARTS_DIR).parent_path() / "machines" / "robot_abb_positioner.json";
}

machine::MachineConfig robot_config() {
  auto m = machine::parse_machine(slurp(robot_machine()), "robot");
  EXPECT_TRUE(m.ok()) << m.error().message;
  return m.value();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Plans PART on the robot cell into DIR with EXTRA options; checks what every robot plan must show.
nlohmann::json plan_on_robot(const std::string& part, const std::filesystem::path& dir, const std::string& name, const std::string& extra = "") {
  const auto r = run_cli(fmt::format("plan '{}' --no-html --machine '{}' -o '{}' {}", part, robot_machine().string(), dir.string(), extra));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return {};
  const auto report = read_json(dir / "report.json");
  EXPECT_EQ(report["collisions"].get<int>(), 0) << report["collision_list"];
  const auto& robot = report["robot"];
  EXPECT_GT(robot["targets"].get<int>(), 0);
  EXPECT_EQ(robot["configuration_changes"].get<int>(), 0);
  EXPECT_GE(robot["min_joint_margin_deg"].get<double>(), 0.0);
  EXPECT_GT(robot["min_wrist_deg"].get<double>(), 5.0);  // the torch hangs down: the wrist is bent
  // The module, read back by the tests' own reader onto the plan's program points.
  const std::string module = slurp(dir / (name + ".mod"));
  EXPECT_EQ(module.rfind("MODULE polyaxis_plan", 0), 0u);
  EXPECT_NE(module.find("ENDMODULE"), std::string::npos);
  auto program = report::read_plan_program(slurp(dir / "plan.json"), "plan.json");
  EXPECT_TRUE(program.ok());
  const RapidReplay rr = replay_rapid(robot_config(), module, program.value());
  EXPECT_EQ(rr.unreachable, 0u) << rr.first_problem;
  EXPECT_EQ(rr.off_plan, 0u) << rr.first_problem;
  EXPECT_GE(rr.on_plan, rr.targets * 95 / 100) << rr.turns;
  EXPECT_LT(rr.worst_fk_mm, 1e-6);
  EXPECT_EQ(robot["targets"].get<std::size_t>(), rr.targets);
  // And by the build read-back: head, grounding, stalls.
  check_readback(dir, name, false, nullptr, robot_machine());
  return report;
}

TEST(PlanRobot, CylWalls5DecomposedIsSupportFreeAndTheArmReachesEveryTarget) {
  TempDir dir;
  const std::string part = std::string(POLYAXIS_PARTS_DIR) + "/cyl_walls5.stl";
  const auto report = plan_on_robot(part, dir.path(), "cyl_walls5", "--decompose");
  ASSERT_FALSE(report.is_null());
  EXPECT_TRUE(report["support_free"].get<bool>()) << report["unsupported_area_mm2"];
  EXPECT_GT(report["regions"].get<int>(), 1);
  // The library's own reader agrees: simulate reads the module against the plan.
  const auto sim = run_cli(fmt::format("simulate '{}' --machine '{}' --plan '{}' --json", (dir / "cyl_walls5.mod").string(),
                                       robot_machine().string(), (dir / "plan.json").string()));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto j = nlohmann::json::parse(sim.out);
  EXPECT_EQ(j["limit_violations"].get<int>(), 0);
  EXPECT_LE(j["max_tip_deviation_mm"].get<double>(), 0.01);
}

TEST(PlanRobot, ABentBarOfOurOwnTurnsOnThePositioner) {
  // A round bar bent 70 degrees: its arm's underside needs the part turned under the torch.
  TempDir dir;
  const auto stl = dir / "bar70.stl";
  write_file(stl, binary_stl(bent_bar(40.0, 6.0, 70.0, 28, 20)));
  const auto report = plan_on_robot(stl.string(), dir / "out", "bar70");
  ASSERT_FALSE(report.is_null());
  EXPECT_TRUE(report["support_free"].get<bool>()) << report["unsupported_area_mm2"];
  const auto tilt = report["axis_ranges"]["tilt"];
  EXPECT_GT(tilt[1].get<double>() - tilt[0].get<double>(), 20.0);  // the positioner tilts the part
}

TEST(PlanRobot, ArcInstructionsBracketEveryBead) {
  TempDir dir;
  std::string process = std::string(process::default_process_json());
  process.replace(process.rfind('}'), 1, R"(, "rapid": {"switch": "arc", "seam": "seamWaam", "weld": "weldWaam"}})");
  write_file(dir / "arc.json", process);
  const std::string part = std::string(POLYAXIS_PARTS_DIR) + "/l_block.stl";
  const auto r = run_cli(fmt::format("plan '{}' --no-html --machine '{}' --process '{}' -o '{}'", part, robot_machine().string(),
                                     (dir / "arc.json").string(), (dir / "out").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string module = slurp(dir / "out" / "l_block.mod");
  EXPECT_EQ(count(module, "SetDO"), 0u);
  const std::size_t starts = count(module, "ArcLStart "), ends = count(module, "ArcLEnd ");
  EXPECT_GT(starts, 10u);
  EXPECT_EQ(starts, ends);
  EXPECT_NE(module.find("seamWaam,weldWaam,"), std::string::npos);
  // Starts and ends alternate, and every ArcL lies between them.
  std::istringstream in(module);
  std::string line;
  bool welding = false;
  while (std::getline(in, line)) {
    if (line.find("ArcLStart ") != std::string::npos) {
      EXPECT_FALSE(welding) << line;
      welding = true;
    } else if (line.find("ArcLEnd ") != std::string::npos) {
      EXPECT_TRUE(welding) << line;
      welding = false;
    } else if (line.find("ArcL ") != std::string::npos) {
      EXPECT_TRUE(welding) << line;
    }
  }
  EXPECT_FALSE(welding);
  // The library's reader takes the arc as the process: the build read-back holds.
  auto p = process::parse_process(process, "arc");
  ASSERT_TRUE(p.ok()) << p.error().message;
  const auto report = read_json(dir / "out" / "report.json");
  EXPECT_GT(report["build_check"]["process_on_s"].get<double>(), 0.0);
  EXPECT_EQ(report["build_check"]["head_collisions"].get<int>(), 0);
}

TEST(PlanRobot, APositionerOutOfTheArmsReachIsRefusedNamingIt) {
  TempDir dir;
  std::string text = slurp(robot_machine());
  const std::string from = R"("origin_mm": [1000, 0, 500])";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), R"("origin_mm": [2600, 0, 500])");
  write_file(dir / "far.json", text);
  const std::string part = std::string(POLYAXIS_PARTS_DIR) + "/l_block.stl";
  const auto r = run_cli(fmt::format("plan '{}' --no-html --machine '{}' -o '{}'", part, (dir / "far.json").string(), (dir / "out").string()));
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_NE(r.err.find("the robot cannot reach it"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "l_block.mod"));
}

}  // namespace
}  // namespace polyaxis::test
