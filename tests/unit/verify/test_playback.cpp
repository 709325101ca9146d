// The playback frames (verify/playback.h) of hand-written programs: one per motion block and per
// dwell, each with its line, its end pose, the process state, and the time it ends on the
// machine's clock: the build-time estimate's (feeds and the axes' limits, acceleration, blends),
// dwells by P.
#include <gtest/gtest.h>

#include "polyaxis/verify/playback.h"
#include "polyaxis/verify/simulate.h"
#include "support/programs.h"

namespace polyaxis::verify {
namespace {

using namespace polyaxis::test;

TEST(Playback, FramesCarryLinePoseProcessAndTheMachinesClock) {
  // linear maximum 6000 mm/min and 1000 mm/s², rotary 3600 deg/min and 3600 deg/s²
  const auto m = example_machine("ded5_ac");
  const auto p = default_process();           // process codes M64 P0 / M65 P0
  const std::string program =
      "G21 G90 G94 G17\n"
      "(layer 0 region 0 approach)\n"
      "G0 X0 Y0 Z10 A0 C0\n"                  // line 3: the first move (the machine was anywhere): t 0
      "G0 X0 Y0 Z0 A0 C0\n"                   // line 4: a rapid of 10 mm, up to 100 mm/s and down: 0.2 s
      "M64 P0\n"
      "G4 P0.5\n"                             // line 6: a dwell of 0.5 s, the process on
      // line 7: 60 mm at 10 mm/s, ramps at half the acceleration (a parabolic blend into the
      // turn): 6.02 s, less the blend's overlap, 10 / 500 s: 6 s
      "G1 X60 Y0 Z0 A0 C0 F600\n"
      // line 8: a turn of 90 deg at 30 deg/s, at 1800 deg/s² from the blend to a stop: 3 + 1/60 s
      "G1 X60 Y0 Z0 A0 C90 F1800\n"
      "M65 P0\n"
      "(layer 1 region 2 perimeter 0)\n"
      "G0 X60 Y0 Z0 A0 C0\n"                  // line 11: a rapid turn of 90 deg at 60 deg/s: 1.5 + 1/60 s
      "M2\n";
  auto frames = playback_frames(m, p, program);
  ASSERT_TRUE(frames.ok()) << frames.error().message;
  const auto& f = frames.value();
  ASSERT_EQ(f.size(), 6u);
  const std::uint64_t lines[] = {3, 4, 6, 7, 8, 11};
  const double times[] = {0.0, 0.2, 0.7, 6.7, 9.7 + 1.0 / 60.0, 11.2 + 2.0 / 60.0};
  const bool on[] = {false, false, true, true, true, false};
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_EQ(f[i].line, lines[i]) << i;
    EXPECT_NEAR(f[i].time_s, times[i], 1e-9) << i;
    EXPECT_EQ(f[i].process_on, on[i]) << i;
  }
  EXPECT_TRUE(f[1].rapid);
  EXPECT_FALSE(f[3].rapid);
  EXPECT_DOUBLE_EQ(f[3].pose.x_mm, 60.0);
  EXPECT_DOUBLE_EQ(f[4].pose.c_deg, 90.0);
  EXPECT_DOUBLE_EQ(f[2].pose.z_mm, 0.0);  // the dwell holds the pose before it
  EXPECT_EQ(f[0].layer, 0);
  EXPECT_EQ(f[5].layer, 1);
  EXPECT_EQ(f[5].region, 2);
  // The playback's clock ends where report.json's build_time_s does.
  const auto sim = simulate(m, program, {}, &p);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_NEAR(f.back().time_s, sim.value().build_time.total_s, 1e-9);
}

TEST(Playback, MalformedGcodeNamesTheLine) {
  auto frames = playback_frames(example_machine("ded5_ac"), default_process(), "G21\nG1 X1 Y F100\n");
  ASSERT_FALSE(frames.ok());
  EXPECT_NE(frames.error().message.find("line 2"), std::string::npos) << frames.error().message;
}

}  // namespace
}  // namespace polyaxis::verify
