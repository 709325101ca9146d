// A real controller reads our G-code: LinuxCNC's stand-alone interpreter rs274 (Debian
// linuxcnc-uspace, 2.9) must accept every program and move to exactly the positions we wrote.
//
// What rs274 needs and prints (checked with 2.9.0~pre1): `rs274 -g IN.ngc OUT.txt` runs without a
// tool table (-t), parameter file (-v) or INI (-i); it prints "executing" on stdout, writes one
// canonical call per line to OUT.txt ("   12 N..... STRAIGHT_FEED(10.0000, 5.0000, 2.0000,
// 15.0000, 0.0000, 30.0000)" with X Y Z A B C at 4 decimals, SET_FEED_RATE(…), DWELL(…),
// SET_AUX_OUTPUT_BIT(0) for M64 P0, …) and exits 0; on an error it prints the message and the
// offending block and exits 1.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <regex>

#include "polyaxis/post/gcode.h"
#include "support/programs.h"
#include "support/cli.h"

namespace polyaxis::post {
namespace {

using namespace polyaxis::test;

std::string find_rs274() {
  if (std::filesystem::exists("/usr/bin/rs274")) return "/usr/bin/rs274";
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t colon = dirs.find(':', start);
    const std::string dir = dirs.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    if (!dir.empty() && std::filesystem::exists(dir + "/rs274")) return dir + "/rs274";
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  return {};
}

struct Canonical {
  std::vector<std::array<double, 6>> positions;  // STRAIGHT_FEED and STRAIGHT_TRAVERSE, in order
  std::vector<double> feeds;                     // SET_FEED_RATE
};

Canonical parse_canonical(const std::string& text) {
  static const std::regex kMove(R"(STRAIGHT_(FEED|TRAVERSE)\(([^)]*)\))");
  static const std::regex kFeed(R"(SET_FEED_RATE\(([-0-9.]+)\))");
  Canonical c;
  for (const std::string& line : lines_of(text)) {
    std::smatch m;
    if (std::regex_search(line, m, kMove)) {
      std::array<double, 6> p{};
      std::stringstream s(m[2].str());
      std::string item;
      for (std::size_t k = 0; k < 6 && std::getline(s, item, ','); ++k) p[k] = std::stod(item);
      c.positions.push_back(p);
    } else if (std::regex_search(line, m, kFeed)) {
      c.feeds.push_back(std::stod(m[1].str()));
    }
  }
  return c;
}

TEST(Rs274, AcceptsOurProgramsAndMovesWhereWeSaid) {
  const std::string rs274 = find_rs274();
  if (rs274.empty()) GTEST_SKIP() << "rs274 (Debian linuxcnc-uspace) is not installed";
  polyaxis::test::TempDir dir;
  for (const char* name : {"ded5_ac", "ded5_bc"}) {
    SCOPED_TRACE(name);
    const machine::MachineConfig m = example_machine(name);
    auto text = write_gcode(m, default_process(), helix_and_tilt(), GcodeOptions{.rapid_travel = true});
    ASSERT_TRUE(text.ok()) << text.error().message;
    const auto in = dir / (std::string(name) + ".ngc");
    const auto out = dir / (std::string(name) + ".txt");
    const auto log = dir / (std::string(name) + ".log");
    ASSERT_TRUE(save_gcode(in.string(), text.value()).ok());
    // HOME is the test's own directory: rs274 truncates and maps $HOME/.tool.mmap, and runs
    // sharing it die of SIGBUS (plan_checks.h, rs274_command).
    const std::string cmd =
        "HOME='" + dir.path().string() + "' '" + rs274 + "' -g '" + in.string() + "' '" + out.string() + "' > '" + log.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << cmd;
    ASSERT_EQ(WEXITSTATUS(status), 0) << polyaxis::test::slurp(log);

    const Canonical canon = parse_canonical(polyaxis::test::slurp(out));
    const std::vector<Block> ours = motion_blocks(text.value());
    ASSERT_EQ(canon.positions.size(), ours.size());
    ASSERT_GT(ours.size(), 100u);
    for (std::size_t i = 0; i < ours.size(); ++i) {
      for (std::size_t k = 0; k < 6; ++k) {
        ASSERT_NEAR(canon.positions[i][k], ours[i].axes[k], 1e-3) << "block " << i << " axis " << "XYZABC"[k];
      }
    }
    ASSERT_FALSE(canon.feeds.empty());
    for (const double f : canon.feeds) EXPECT_LE(f, std::max(m.feed.linear_max_mm_min, m.feed.rotary_max_deg_min));
  }
}

}  // namespace
}  // namespace polyaxis::post
