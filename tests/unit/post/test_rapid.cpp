// The ABB RAPID post (post/rapid.h) on the robot cell of examples/machines/robot_abb_positioner.json:
// its statements, the process switched at exact stops (SetDO) or by the arc instructions, read back
// by simulate onto the plan, its speeds within the cell's maxima, and the reader's refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "polyaxis/post/rapid.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/verify/simulate.h"
#include "support/programs.h"

namespace polyaxis::post {
namespace {

using namespace polyaxis::test;

// A square at z 1 with the torch tilted 30° outwards on two sides, a turn in place with the process
// on, and a travel away (as the TRAORI test's).
std::vector<ProgramPoint> square() {
  const double s = std::sin(M_PI / 6.0), c = std::cos(M_PI / 6.0);
  std::vector<ProgramPoint> p;
  auto add = [&](core::Vec3 tip, core::Vec3 axis, bool on, double feed = 8.0) {
    ProgramPoint q;
    q.tip_part_mm = tip, q.tool_axis_part = axis, q.process_on = on, q.feed_mm_s = feed, q.layer = 3, q.region = 1;
    p.push_back(q);
  };
  add({0, 0, 5}, {0, 0, 1}, false, 50.0);
  p.back().comment_if_new_block = "approach";
  add({0, 0, 1}, {0, 0, 1}, false, 50.0);
  add({20, 0, 1}, {0, -s, c}, true);
  p.back().comment_if_new_block = "perimeter 0";
  add({20, 20, 1}, {s, 0, c}, true);
  add({0, 20, 1}, {0, 0, 1}, true);
  add({0, 0, 1}, {0, 0, 1}, true);
  add({0, 0, 1}, {-s, 0, c}, true);
  add({0, 0, 10}, {0, 0, 1}, false, 50.0);
  return p;
}

TEST(Rapid, WritesAModuleWhoseTargetsReadBackOntoThePlan) {
  const auto m = example_machine("robot_abb_positioner");
  const auto p = default_process();
  GcodeStats stats;
  GcodeOptions o;
  o.stats = &stats;
  auto text = write_program(m, p, square(), o);
  ASSERT_TRUE(text.ok()) << text.error().message;
  EXPECT_EQ(program_extension(m), ".mod");
  const std::string& t = text.value();
  EXPECT_EQ(t.rfind("MODULE polyaxis_plan\n", 0), 0u);
  EXPECT_NE(t.find("PERS wobjdata wPolyaxis := [FALSE,FALSE,\"STN1\","), std::string::npos);
  EXPECT_NE(t.find("    ! layer 3 region 1 perimeter 0\n"), std::string::npos);
  EXPECT_NE(t.find("ActUnit STN1;"), std::string::npos);
  // Every switch of the process comes after a move that stops exactly there.
  std::istringstream in(t);
  std::string line, previous;
  int switches = 0;
  while (std::getline(in, line)) {
    if (line.find("SetDO doProcess,") != std::string::npos) {
      ++switches;
      EXPECT_NE(previous.find(",fine,"), std::string::npos) << previous;
    }
    if (line.find("Move") != std::string::npos) previous = line;
  }
  EXPECT_EQ(switches, 2);  // on, then off for the turn in place (nothing is laid after it)
  EXPECT_NE(t.find("WaitTime 0.500;"), std::string::npos);
  EXPECT_EQ(t.substr(t.size() - 10), "ENDMODULE\n");
  EXPECT_EQ(stats.robot_targets, 8u);  // the turn in place splits the last deposit move
  EXPECT_EQ(stats.robot_config_changes, 0u);
  auto sim = verify::simulate(m, t, square(), &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u);
  EXPECT_LT(sim.value().max_tip_deviation_mm, 1e-3);
  EXPECT_LT(sim.value().max_axis_deviation_deg, 1e-3);
}

TEST(Rapid, ArcInstructionsStartAndEndEachBead) {
  const auto m = example_machine("robot_abb_positioner");
  auto p = default_process();
  p.rapid.arc = true;
  auto text = write_program(m, p, square());
  ASSERT_TRUE(text.ok()) << text.error().message;
  const std::string& t = text.value();
  EXPECT_EQ(t.find("SetDO"), std::string::npos);
  const std::regex start(R"(ArcLStart \[.*seam1,weld1,fine,tPolyaxis\\WObj:=wPolyaxis;)"), end(R"(ArcLEnd \[.*seam1,weld1,fine,)");
  EXPECT_EQ(std::distance(std::sregex_iterator(t.begin(), t.end(), start), std::sregex_iterator()), 1);  // one bead: the turn in place ends it
  EXPECT_EQ(std::distance(std::sregex_iterator(t.begin(), t.end(), end), std::sregex_iterator()), 1);  // one bead: the turn in place ends it
  auto sim = verify::simulate(m, t, square(), &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_NEAR(sim.value().deposit_length_mm, 80.0, 1e-3);  // the square's four sides, the turn in place not
}

TEST(Rapid, ATurningPositionerSlowsTheSpeedsToTheCellsMaxima) {
  auto m = example_machine("robot_abb_positioner");
  m.feed.rotary_max_deg_min = 60.0;
  const auto p = default_process();
  auto text = write_program(m, p, square());
  ASSERT_TRUE(text.ok()) << text.error().message;
  auto sim = verify::simulate(m, text.value(), square(), &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u) << (sim.value().violations.empty() ? "" : sim.value().violations.front());
}

TEST(Rapid, TheReaderRefusesWhatItCannotRead) {
  const auto m = example_machine("robot_abb_positioner");
  const auto p = default_process();
  const std::string good = write_program(m, p, square()).value();
  auto refused = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) t.replace(at, from.size(), to);
    auto sim = verify::simulate(m, t, {}, &p);
    return sim.ok() ? std::string() : sim.error().message;
  };
  EXPECT_NE(refused("ConfJ \\On;", "TPWrite \"hi\";").find("'TPWrite' is not read"), std::string::npos);
  EXPECT_NE(refused("[[0.0000,0.0000,350.0000]", "[[0.0000,0.0000,300.0000]").find("robot.tcp"), std::string::npos);
  EXPECT_NE(refused("\"STN1\"", "\"STN2\"").find("positioner"), std::string::npos);
  EXPECT_NE(refused("\\WObj:=wPolyaxis;", ";").find("\\WObj"), std::string::npos);
  EXPECT_NE(refused("MODULE polyaxis_plan", "MODULE polyaxis_plan\nMODULE x").find("a second MODULE"), std::string::npos);
  EXPECT_NE(refused("9E+09,9E+09,9E+09,9E+09]]", "9E+99,9E+09,9E+09,9E+09]]").find("number"), std::string::npos);
  const std::string e = refused("DeactUnit STN1;", "DeactUnit STN1");
  EXPECT_NE(e.find("RAPID line"), std::string::npos) << e;
}

TEST(Rapid, AMachineWithoutARobotHasNoRapidPost) {
  auto m = example_machine("ded5_ac");
  EXPECT_EQ(write_rapid(m, default_process(), square()).error().code, core::ErrorCode::kUsage);
}

}  // namespace
}  // namespace polyaxis::post
