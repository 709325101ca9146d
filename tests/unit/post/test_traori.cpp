// The Sinumerik TRAORI post (post/traori.h): its grammar, the tip and tool vector it writes read
// back by simulate onto the plan, its feeds within the machine's axis maxima, a turn in place
// written as a rapid with the process off, the machine file's "post" choosing it, and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "polyaxis/machine/kinematics.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/verify/simulate.h"
#include "support/programs.h"

namespace polyaxis::post {
namespace {

using namespace polyaxis::test;

machine::MachineConfig traori_machine() {
  machine::MachineConfig m = example_machine("ded5_ac");
  m.post = machine::PostDialect::kSiemensTraori;
  return m;
}

// A square at z 1 with the torch tilted 30° outwards on two sides (the axis turns at the corners),
// a turn in place at the end with the process on, and a travel away.
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
  add({0, 0, 1}, {-s, 0, c}, true);  // turn in place: the process must not stay on
  add({0, 0, 10}, {0, 0, 1}, false, 50.0);
  return p;
}

TEST(Traori, WritesTipsAndToolVectorsThatReadBackOntoThePlan) {
  const auto m = traori_machine();
  const auto p = default_process();
  const auto points = square();
  auto text = write_program(m, p, points);
  ASSERT_TRUE(text.ok()) << text.error().message;
  EXPECT_EQ(program_extension(m), ".mpf");
  const std::string num = R"(-?[0-9]+\.[0-9]{4})", vec = R"(-?[0-9]\.[0-9]{6})";
  const std::regex grammar("^(; .*|G17 G90 G71 G94|TRAORI|ORIWKS|ORIVECT|TRAFOOF|M30|G4 F[0-9]+\\.[0-9]{4}|" + p.process_on + "|" + p.process_off +
                           "|G[01] X" + num + " Y" + num + " Z" + num + " A3=" + vec + " B3=" + vec + " C3=" + vec + "( F[0-9]+\\.[0-9])?)$");
  std::istringstream in(text.value());
  std::string line, last;
  int blocks = 0, turn_in_place = 0;
  bool on = false;
  while (std::getline(in, line)) {
    EXPECT_TRUE(std::regex_match(line, grammar)) << line;
    if (line == p.process_on) on = true;
    if (line == p.process_off) on = false;
    if (line.rfind("G0 X0.0000 Y0.0000 Z1.0000 A3=-0.5", 0) == 0) {
      ++turn_in_place;
      EXPECT_FALSE(on) << "the process is on during a turn in place";
    }
    blocks += line.rfind("G", 0) == 0 && line.find(" X") != std::string::npos;
    last = line;
  }
  EXPECT_EQ(turn_in_place, 1);
  EXPECT_EQ(last, "M30");
  EXPECT_NE(text.value().find("; layer 3 region 1 perimeter 0"), std::string::npos);
  EXPECT_NE(text.value().find("G4 F0.5000"), std::string::npos);
  // simulate reads it the same way the controller moves: tips straight, vectors on great circles.
  auto sim = verify::simulate(m, text.value(), points, &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u);
  EXPECT_LT(sim.value().max_tip_deviation_mm, 1e-3);
  EXPECT_LT(sim.value().max_axis_deviation_deg, 1e-3);
  EXPECT_EQ(sim.value().moves, static_cast<std::uint64_t>(blocks));
}

TEST(Traori, FeedsAreSlowedToTheAxesMaxima) {
  // A slow rotary axis: the corners' turn of the vector sets the block's time, not the tip's feed.
  auto m = traori_machine();
  m.feed.rotary_max_deg_min = 60.0;
  const auto p = default_process();
  GcodeStats stats;
  GcodeOptions o;
  o.stats = &stats;
  auto text = write_program(m, p, square(), o);
  ASSERT_TRUE(text.ok()) << text.error().message;
  EXPECT_GT(stats.rotary_limited, 0u);
  auto sim = verify::simulate(m, text.value(), square(), &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u) << (sim.value().violations.empty() ? "" : sim.value().violations.front());
}

TEST(Traori, UnreachablePointsAndThreeAxisMachinesAreRefused) {
  auto m = traori_machine();
  m.tilt_deg = {-10.0, 10.0};  // the 30° tilts are out of reach
  auto text = write_program(m, default_process(), square());
  ASSERT_FALSE(text.ok());
  EXPECT_EQ(text.error().code, core::ErrorCode::kMachineLimit);
  EXPECT_NE(text.error().message.find("move to point"), std::string::npos) << text.error().message;
  auto three = example_machine("gantry3");
  EXPECT_FALSE(write_traori(three, default_process(), square()).ok());
  // The machine file chooses the post, and refuses it on a 3-axis machine or misspelt.
  std::string json(machine::default_machine_json());
  json.insert(json.rfind('}'), R"(, "post": "siemens-traori")");
  auto parsed = machine::parse_machine(json, "m.json");
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(parsed.value().post, machine::PostDialect::kSiemensTraori);
  std::string misspelt = json;
  misspelt.replace(misspelt.find("siemens-traori"), 14, "sinumerik");
  auto bad = machine::parse_machine(misspelt, "m.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("supported: linuxcnc, siemens-traori"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace polyaxis::post
