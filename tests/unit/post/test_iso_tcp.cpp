// The ISO TCP post (post/iso_tcp.h): its grammar, the tip and the rotary axes it writes read back
// by simulate onto the plan (tip straight, axes linear), the tests' own reading of the same
// program through forward kinematics of the written angles, feeds within the axis maxima, a turn
// in place with the process off, the set id under the leading "%", and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "polyaxis/machine/kinematics.h"
#include "polyaxis/post/iso_tcp.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/verify/simulate.h"
#include "support/programs.h"

namespace polyaxis::post {
namespace {

using namespace polyaxis::test;

machine::MachineConfig iso_machine(const std::string& file = "ded5_ac") {
  machine::MachineConfig m = example_machine(file);
  m.post = machine::PostDialect::kIsoTcp;
  return m;
}

TEST(IsoTcp, WritesTipsAndRotaryAxesThatReadBackOntoThePlan) {
  for (const std::string file : {"ded5_ac", "ded5_bc", "ded5_head_bc"}) {
    const auto m = iso_machine(file);
    const auto p = default_process();
    const auto points = helix_and_tilt();
    auto text = write_program(m, p, points);
    ASSERT_TRUE(text.ok()) << file << ": " << text.error().message;
    EXPECT_EQ(program_extension(m), ".nc");
    const char t = machine::tilt_axis_letter(m.kind);
    const std::string num = R"(-?[0-9]+\.[0-9]{4})";
    const std::regex grammar("^(%|\\(.*\\)|G21 G90 G94 G17|G43\\.4 H1|G49|M30|G4 X[0-9]+\\.[0-9]{4}|" + p.process_on + "|" + p.process_off +
                             "|G[01] X" + num + " Y" + num + " Z" + num + " " + t + num + " C" + num + "( F[0-9]+\\.[0-9])?)$");
    std::istringstream in(text.value());
    std::string line, first, last;
    std::size_t lines = 0;
    while (std::getline(in, line)) {
      EXPECT_TRUE(std::regex_match(line, grammar)) << file << ": " << line;
      if (lines++ == 0) first = line;
      last = line;
    }
    EXPECT_EQ(first, "%");
    EXPECT_EQ(last, "%");
    // The library's reader: the tip within the path tolerance of the plan, no limit broken.
    auto sim = verify::simulate(m, text.value(), points, &p, 0.01);
    ASSERT_TRUE(sim.ok()) << file << ": " << sim.error().message;
    EXPECT_EQ(sim.value().limit_violations, 0u) << file;
    EXPECT_LE(sim.value().max_tip_deviation_mm, 0.01) << file;
    // Our own reading: each G1/G0 block's X Y Z is a program point's tip, and the forward
    // kinematics of its written angles its tool axis.
    std::size_t at = 0, matched = 0;
    const std::regex block("^G[01] X(" + num + ") Y(" + num + ") Z(" + num + ") [AB](" + num + ") C(" + num + ")");
    std::istringstream again(text.value());
    while (std::getline(again, line)) {
      std::smatch b;
      if (!std::regex_search(line, b, block)) continue;
      const core::Vec3 tip{std::stod(b[1]), std::stod(b[2]), std::stod(b[3])};
      machine::MachinePose angles{};
      angles.a_or_b_deg = std::stod(b[4]), angles.c_deg = std::stod(b[5]);
      const core::Vec3 axis = core::normalized(machine::forward(m, angles).tool_axis_part);
      for (std::size_t k = at; k < points.size(); ++k) {
        if (core::norm(points[k].tip_part_mm - tip) <= 1e-4 && core::norm(core::normalized(points[k].tool_axis_part) - axis) <= 1e-5) {
          at = k, ++matched;
          break;
        }
      }
    }
    EXPECT_EQ(matched, points.size()) << file;
  }
}

TEST(IsoTcp, FeedsStayWithinTheAxisMaximaAndTurnsInPlaceAreTravel) {
  auto m = iso_machine();
  m.feed.rotary_max_deg_min = 600.0;
  const auto p = default_process();
  auto points = helix_and_tilt();
  // A turn in place with the process on.
  ProgramPoint turn = points[20];
  turn.tool_axis_part = {0, 0, 1};
  points.insert(points.begin() + 21, turn);
  auto text = write_program(m, p, points);
  ASSERT_TRUE(text.ok()) << text.error().message;
  auto sim = verify::simulate(m, text.value(), points, &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u) << (sim.value().violations.empty() ? "" : sim.value().violations.front());
  // Every G0 is written with the process off.
  std::istringstream in(text.value());
  std::string line;
  bool on = false;
  int rapids = 0;
  while (std::getline(in, line)) {
    if (line == p.process_on) on = true;
    if (line == p.process_off) on = false;
    if (line.rfind("G0 ", 0) == 0) {
      ++rapids;
      EXPECT_FALSE(on) << line;
    }
  }
  EXPECT_GE(rapids, 2);
}

// Under G43.4 the rotary axes turn linearly inside a block, so a torch tilted 40° whose azimuth
// turns 45° between two points would sweep a cone 3° off the plan's great circle: the post writes
// such blocks in pieces along it, and slows each to its own axes' maxima.
TEST(IsoTcp, BlocksThatWouldBendTheAxisOffThePlanAreWrittenInPieces) {
  const auto m = iso_machine();
  const auto p = default_process();
  const double tilt = 40.0 * M_PI / 180.0;
  std::vector<ProgramPoint> points;
  for (int k = 0; k <= 16; ++k) {
    const double az = k * M_PI / 4.0;
    ProgramPoint q;
    q.tip_part_mm = {30.0 * std::cos(az), 30.0 * std::sin(az), 2.0};
    q.tool_axis_part = {std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt)};
    q.feed_mm_s = k == 0 ? 50.0 : 8.0;
    q.process_on = k > 0;
    points.push_back(q);
  }
  auto text = write_program(m, p, points);
  ASSERT_TRUE(text.ok()) << text.error().message;
  auto sim = verify::simulate(m, text.value(), points, &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u) << (sim.value().violations.empty() ? "" : sim.value().violations.front());
  EXPECT_LE(sim.value().max_tip_deviation_mm, 0.01);
  EXPECT_LE(sim.value().max_axis_deviation_deg, 0.1);
  EXPECT_GT(std::count(text.value().begin(), text.value().end(), '\n'), 16 * 4);  // pieces, not 16 blocks
}

TEST(IsoTcp, TheSetIdGoesUnderThePercentLine) {
  auto text = write_program(iso_machine(), default_process(), helix_and_tilt());
  ASSERT_TRUE(text.ok());
  auto stamped = with_set_id(iso_machine(), text.value(), "0123456789abcdef");
  ASSERT_TRUE(stamped.ok());
  EXPECT_EQ(stamped.value().rfind("%\n(polyaxis: machine ded5_ac [xyzac-trt], process ded_steel, post iso-tcp, set 0123456789abcdef)\n", 0), 0u)
      << stamped.value().substr(0, 200);
  EXPECT_EQ(std::count(stamped.value().begin(), stamped.value().end(), '\n'), std::count(text.value().begin(), text.value().end(), '\n'));
}

TEST(IsoTcp, RefusesWhatItCannotWriteOrRead) {
  const auto p = default_process();
  auto gantry = example_machine("gantry3");
  gantry.post = machine::PostDialect::kIsoTcp;
  auto three = write_program(gantry, p, helix_and_tilt());
  ASSERT_FALSE(three.ok());
  EXPECT_EQ(three.error().code, core::ErrorCode::kUsage);
  EXPECT_FALSE(machine::parse_machine(R"({"name": "g", "kinematics": "xyz", "limits": {"x": {"min": 0, "max": 1}, "y": {"min": 0, "max": 1},
      "z": {"min": 0, "max": 1}}, "post": "iso-tcp"})", "g").ok());
  // Motion before G43.4 is refused naming the line.
  auto sim = verify::simulate(iso_machine(), "G21 G90 G94 G17\nG0 X1 Y2 Z3 A0 C0\n", {}, &p);
  ASSERT_FALSE(sim.ok());
  EXPECT_NE(sim.error().message.find("line 2: motion without G43.4"), std::string::npos) << sim.error().message;
}

}  // namespace
}  // namespace polyaxis::post
