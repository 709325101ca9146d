// A head-head machine (issue 15, item 1: examples/machines/ded5_head_bc.json, LinuxCNC 5axiskins'
// B/C head with its pivot length): the part stays fixed, so gravity does not turn with a region's
// build direction. With the default process every region is built straight up and only the torch
// tilts; a process that deposits off vertical (off_vertical_max_deg) lets the decomposition turn
// regions that far and no further. Every program is read back through the head's kinematics by the
// tests' own reader, and rs274 accepts it.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "support/cli.h"
#include "support/meshes.h"
#include "support/plan_checks.h"
#include "support/readback.h"

namespace polyaxis::test {
namespace {

std::filesystem::path head_machine() {
  return std::filesystem::path(POLYAXIS_PARTS_DIR).parent_path() / "machines" / "ded5_head_bc.json";
}

double degrees_off_vertical(const nlohmann::json& d) {
  const double x = d[0].get<double>(), y = d[1].get<double>(), z = d[2].get<double>();
  return std::atan2(std::hypot(x, y), z) * 180.0 / M_PI;
}

TEST(PlanHeadHead, EveryRegionGrowsStraightUpAndTheHeadTiltsTheTorch) {
  // Flared cups (solid frusta 37-40 deg over, past the process's 30 deg) on the fixed table: the
  // head tilts the torch out all round, so every loop turns C a whole turn, and C (+-720 deg) is
  // unwound between loops.
  struct Cup {
    const char* name;
    double r0, r1, h;
    std::uint32_t sides;
  };
  for (const Cup& cup : {Cup{"cup_40deg", 10, 20, 12, 64}, Cup{"cup_37deg", 8, 17, 12, 40}}) {
    SCOPED_TRACE(cup.name);
    TempDir dir;
    const auto stl = dir / (std::string(cup.name) + ".stl");
    write_file(stl, binary_stl(frustum(cup.r0, cup.r1, cup.h, cup.sides)));
    const auto out = dir / "out";
    const auto r = run_cli(fmt::format("plan '{}' --no-html --machine '{}' -o '{}'", stl.string(), head_machine().string(), out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = read_json(out / "report.json");
    const auto plan = read_json(out / "plan.json");
    EXPECT_TRUE(report["support_free"].get<bool>()) << report["unsupported_area_mm2"];
    EXPECT_EQ(report["collisions"].get<int>(), 0);
    EXPECT_EQ(plan["kinematics"], "xyzbc-head");
    for (const auto& region : plan["regions"]) EXPECT_LT(degrees_off_vertical(region["build_direction"]), 1e-9);
    // The torch tilts (B moves), C stays within its stops, and the program's words are X Y Z B C.
    const auto tilt = report["axis_ranges"]["tilt"];
    EXPECT_GT(tilt[1].get<double>() - tilt[0].get<double>(), 10.0);
    const auto c = report["axis_ranges"]["c"];
    EXPECT_GE(c[0].get<double>(), -720.0 - 1e-6);
    EXPECT_LE(c[1].get<double>(), 720.0 + 1e-6);
    const auto ngc = out / (std::string(cup.name) + ".ngc");
    const std::string gcode = slurp(ngc);
    EXPECT_NE(gcode.find(" B"), std::string::npos);
    EXPECT_EQ(gcode.find(" A"), std::string::npos);
    check_readback(out, cup.name, false, nullptr, head_machine());
    const auto sim = run_cli(fmt::format("simulate '{}' --machine '{}' --plan '{}' --json", ngc.string(), head_machine().string(),
                                         (out / "plan.json").string()));
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto s = nlohmann::json::parse(sim.out);
    EXPECT_EQ(s["limit_violations"].get<int>(), 0);
    EXPECT_LE(s["max_tip_deviation_mm"].get<double>(), 0.01);
    expect_rs274_reads(out, ngc);
  }
}

TEST(PlanHeadHead, RegionsTurnOffVerticalOnlyAsFarAsTheProcessDeposits) {
  // The L-block's arm wants to grow along +X. On the fixed part with the default process (0 deg
  // off vertical) it cannot: one region, with its overhang, and the warning names the process
  // key. A process that deposits 80 deg off vertical lets the arm lean that far and no further.
  const std::string part = std::string(POLYAXIS_PARTS_DIR) + "/l_block.stl";
  {
    TempDir dir;
    const auto r = run_cli(fmt::format("plan '{}' --strategy decompose --no-html --machine '{}' -o '{}'", part, head_machine().string(),
                                       dir.path().string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("off_vertical_max_deg"), std::string::npos) << r.err;
    const auto plan = read_json(dir / "plan.json");
    for (const auto& region : plan["regions"]) EXPECT_LT(degrees_off_vertical(region["build_direction"]), 1e-9);
    EXPECT_FALSE(read_json(dir / "report.json")["support_free"].get<bool>());
    check_readback(dir.path(), "l_block", false, nullptr, head_machine());
  }
  {
    // 80 deg: the arm leans that far (and no further) and is support-free. (Auto turns the L over
    // instead: the arm on the plate, the column rising from it, one region upright.)
    TempDir dir;
    const auto r = run_cli(fmt::format("plan '{}' --strategy decompose --no-html --machine '{}' --set process.off_vertical_max_deg=80 -o '{}'",
                                       part, head_machine().string(), dir.path().string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto plan = read_json(dir / "plan.json");
    const auto report = read_json(dir / "report.json");
    double most = 0.0;
    for (const auto& region : plan["regions"]) most = std::max(most, degrees_off_vertical(region["build_direction"]));
    EXPECT_EQ(report["regions"].get<int>(), 2);
    EXPECT_LE(most, 80.0 + 1e-6);
    EXPECT_GT(most, 79.0);
    EXPECT_TRUE(report["support_free"].get<bool>()) << report["unsupported_area_mm2"];
    EXPECT_EQ(report["collisions"].get<int>(), 0);
    check_readback(dir.path(), "l_block", false, nullptr, head_machine());
    expect_rs274_reads(dir.path(), dir.path() / "l_block.ngc");
    // The simulation finds the program on the plan, the tool axis too. (Regression: where a travel
    // turned the head 60 deg in place, the tip 0.014 mm along the next move was measured against
    // the move before the turn, and simulate reported 29.5 deg that were not there.)
    const auto sim = run_cli(fmt::format("simulate '{}' --machine '{}' --plan '{}' --json", (dir.path() / "l_block.ngc").string(),
                                         head_machine().string(), (dir.path() / "plan.json").string()));
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto s = nlohmann::json::parse(sim.out);
    EXPECT_LE(s["max_tip_deviation_mm"].get<double>(), 0.01);
    EXPECT_LE(s["max_axis_deviation_deg"].get<double>(), 0.01);
    // `view` rewrites the page from plan.json; with the G-code and its machine the page plays it
    // back, and G-code that does not belong to the machine named is refused naming its line.
    const auto page = dir.path() / "view.html";
    const auto plain = run_cli(fmt::format("view '{}' -o '{}'", (dir.path() / "plan.json").string(), page.string()));
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_EQ(slurp(page).find("\"playback\":"), std::string::npos);
    const auto played = run_cli(fmt::format("view '{}' -o '{}' --gcode '{}' --machine '{}' --set process.off_vertical_max_deg=80",
                                            (dir.path() / "plan.json").string(), page.string(), (dir.path() / "l_block.ngc").string(),
                                            head_machine().string()));
    ASSERT_EQ(played.exit_code, 0) << played.err;
    EXPECT_NE(slurp(page).find("\"playback\":{\"kinematics\":\"xyzbc-head\""), std::string::npos);
    const auto other = dir.path() / "other.html";
    const auto refused = run_cli(fmt::format("view '{}' -o '{}' --gcode '{}'", (dir.path() / "plan.json").string(), other.string(),
                                             (dir.path() / "l_block.ngc").string()));
    EXPECT_EQ(refused.exit_code, 3) << refused.err;
    EXPECT_NE(refused.err.find("B word"), std::string::npos) << refused.err;
    EXPECT_FALSE(std::filesystem::exists(other));
  }
  {
    // 60 deg: the arm's direction is out of reach; the decomposition says which key would help.
    TempDir dir;
    const auto r = run_cli(fmt::format("plan '{}' --strategy decompose --no-html --machine '{}' --set process.off_vertical_max_deg=60 -o '{}'",
                                       part, head_machine().string(), dir.path().string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("within 60 deg of vertical"), std::string::npos) << r.err;
    for (const auto& region : read_json(dir / "plan.json")["regions"]) EXPECT_LE(degrees_off_vertical(region["build_direction"]), 60.0 + 1e-6);
  }
}

}  // namespace
}  // namespace polyaxis::test
