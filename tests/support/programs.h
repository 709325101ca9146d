// Machines and synthetic programs shared by the post and verify tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "polyaxis/post/program.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::test {

using post::ProgramPoint;

inline machine::MachineConfig example_machine(const std::string& name) {
  std::ifstream in(std::string(POLYAXIS_EXAMPLES_DIR) + "/machines/" + name + ".json", std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  auto m = machine::parse_machine(s.str(), name);
  EXPECT_TRUE(m.ok()) << name;
  return m.ok() ? m.value() : machine::MachineConfig{};
}

inline process::ProcessConfig default_process() { return process::parse_process(process::default_process_json(), "p").value(); }

// A helix of radius 40 mm climbing 0.05 mm per 10° step, the tool tilted outwards by 20-30°
// (varying), preceded and followed by vertical travel moves: every axis moves, C turns twice.
inline std::vector<ProgramPoint> helix_and_tilt(int steps = 72) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  std::vector<ProgramPoint> pts;
  pts.push_back({{40.0, 0.0, 30.0}, {0.0, 0.0, 1.0}, 50.0, false, 0, 0, "approach"});
  for (int k = 0; k <= steps; ++k) {
    const double az = k * 10.0 * kDeg, tilt = (25.0 + 5.0 * std::sin(k / 7.0)) * kDeg;
    ProgramPoint p;
    p.tip_part_mm = {40.0 * std::cos(az), 40.0 * std::sin(az), 2.0 + 0.05 * k};
    p.tool_axis_part = {std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt)};
    p.feed_mm_s = k == 0 ? 50.0 : 8.0;
    p.process_on = k > 0;
    p.layer = static_cast<std::uint32_t>(k / 36);
    p.comment_if_new_block = (k % 36 == 0) ? "perimeter" : "";
    pts.push_back(p);
  }
  pts.push_back({{0.0, 0.0, 60.0}, {0.0, 0.0, 1.0}, 50.0, false, 2, 0, "retract"});
  return pts;
}

// The lines of TEXT, without the final empty one.
inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string line;
  while (std::getline(s, line)) out.push_back(line);
  return out;
}

// Positions (X Y Z A B C) of every G0/G1 block, A or B zero when absent.
struct Block {
  bool rapid = false;
  std::array<double, 6> axes{};
  double f = 0.0;  // 0 when the block has no F
};

inline std::vector<Block> motion_blocks(const std::string& text) {
  static const std::regex kWord(R"(([XYZABCF])(-?[0-9]+\.[0-9]+))");
  std::vector<Block> blocks;
  for (const std::string& line : lines_of(text)) {
    if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
    Block b;
    b.rapid = line[1] == '0';
    for (auto it = std::sregex_iterator(line.begin(), line.end(), kWord); it != std::sregex_iterator(); ++it) {
      const char letter = (*it)[1].str()[0];
      const double v = std::stod((*it)[2].str());
      if (letter == 'F') b.f = v;
      else b.axes[std::string("XYZABC").find(letter)] = v;
    }
    blocks.push_back(b);
  }
  return blocks;
}

}  // namespace polyaxis::test
