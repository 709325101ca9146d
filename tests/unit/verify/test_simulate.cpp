// The simulator: parsing, limits, feeds, lengths and times of hand-written programs.
#include <gtest/gtest.h>

#include "polyaxis/post/gcode.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/verify/simulate.h"
#include "support/programs.h"

namespace polyaxis::verify {
namespace {

using core::ErrorCode;
using namespace polyaxis::test;
using post::write_gcode;
using post::GcodeOptions;

core::Error sim_error(const machine::MachineConfig& m, const std::string& text) {
  auto r = simulate(m, text, {});
  EXPECT_FALSE(r.ok()) << text;
  return r.ok() ? core::Error{} : r.error();
}

TEST(Simulate, MalformedGcodeNamesTheLine) {
  const auto m = example_machine("ded5_ac");
  for (const auto& [text, line] : std::vector<std::pair<std::string, std::string>>{
           {"G21\nG90\nG1 X1 Y F100\n", "line 3"},
           {"G21\n(unclosed\n", "line 2"},
           {"G2 X1 Y1 I1 J0 F100\n", "line 1"},
           {"G20\n", "line 1"},
           {"G91\n", "line 1"},
           {"G0 X0 Y0 Z0\nG1 B5 F100\n", "line 2"},
           {"G0 X0\nG1 X5\n", "line 2"},
           {"G1 X1 F100 #1\n", "line 1"},
           {"G0 X0\nG93\nG1 X1\n", "line 3"},
           {"X5\n", "line 1"},
           {"G0 X0\nG0 X", "line 2"},
           {"G0 X1.2.3\n", "line 1"}}) {
    const core::Error e = sim_error(m, text);
    EXPECT_EQ(e.code, ErrorCode::kInvalidInput) << text;
    EXPECT_NE(e.message.find(line), std::string::npos) << e.message;
  }
  EXPECT_NE(sim_error(example_machine("gantry3"), "G0 X0 Y0 Z0 C10\n").message.find("no C axis"), std::string::npos);
}

TEST(Simulate, LengthsTimesAndProcess) {
  const auto m = example_machine("gantry3");
  const auto proc = default_process();
  const std::string text =
      "G21 G90 G94 G17\n"
      "G0 X10 Y10 Z1 ; start\n"
      "M64 P0\n"
      "G1 X20 Y10 Z1 F600\n"
      "G1 X20 Y20 (side two)\n"
      "M65 P0\n"
      "G1 X10 Y20\n"
      "G93\n"
      "G1 X10 Y10 F2\n"
      "M2\n"
      "G0 X999\n";  // after M2: ignored
  auto r = simulate(m, text, {}, &proc);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const SimulationReport& s = r.value();
  EXPECT_EQ(s.moves, 5u);
  EXPECT_EQ(s.rapid_moves, 1u);
  EXPECT_DOUBLE_EQ(s.path_length_mm, 40.0);
  EXPECT_DOUBLE_EQ(s.deposit_length_mm, 20.0);
  EXPECT_DOUBLE_EQ(s.feed_time_s, 3.0 + 30.0);  // 30 mm at 600 mm/min, then 1/2 min in G93
  EXPECT_EQ(s.x_mm.min, 10.0);
  EXPECT_EQ(s.x_mm.max, 20.0);
  EXPECT_TRUE(s.program_end);
  EXPECT_EQ(s.limit_violations, 0u);
}

TEST(Simulate, LimitAndFeedViolationsAreCountedNotFatal) {
  const auto m = example_machine("ded5_ac");  // X ±400, A ±120, 6000 mm/min, 3600 deg/min
  const std::string text =
      "G0 X0 Y0 Z0 A0 C0\n"
      "G1 X500 F100\n"
      "G1 X0\n"
      "G0 A130\n"
      "G0 A0\n"
      "G1 X10 F9000\n"
      "G1 C90 F4000\n"
      "G1 X11 C450 F100\n";
  auto r = simulate(m, text, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().limit_violations, 5u);
  ASSERT_EQ(r.value().violations.size(), 5u);
  EXPECT_NE(r.value().violations[0].find("line 2: X = 500.0000"), std::string::npos) << r.value().violations[0];
  EXPECT_NE(r.value().violations[1].find("line 4: A = 130.0000"), std::string::npos) << r.value().violations[1];
  EXPECT_NE(r.value().violations[2].find("line 6: XYZ feed"), std::string::npos) << r.value().violations[2];
  EXPECT_NE(r.value().violations[3].find("line 7: rotary feed"), std::string::npos) << r.value().violations[3];
  // 1 mm of X at F100 takes 0.01 min while C turns 360°: 36000 deg/min.
  EXPECT_NE(r.value().violations[4].find("line 8: rotary feed 36000"), std::string::npos) << r.value().violations[4];
}

TEST(Simulate, EveryTruncatedPrefixIsReadOrRefused) {
  const auto m = example_machine("ded5_bc");
  const auto plan = helix_and_tilt(6);
  auto text = write_gcode(m, default_process(), plan);
  ASSERT_TRUE(text.ok());
  for (std::size_t n = 0; n <= text.value().size(); ++n) {
    auto r = simulate(m, std::string_view(text.value()).substr(0, n), plan);
    if (!r.ok()) {
      EXPECT_EQ(r.error().code, ErrorCode::kInvalidInput) << n;
    }
  }
}

}  // namespace
}  // namespace polyaxis::verify
