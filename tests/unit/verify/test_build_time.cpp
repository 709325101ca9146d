// The build-time estimate (src/verify/build_time.h): each rule of LinuxCNC's trajectory planner it
// follows, on blocks whose time is known in closed form, and the parts of a program's time.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/verify/simulate.h"
#include "support/programs.h"
#include "verify/build_time.h"

namespace polyaxis::verify::detail {
namespace {

using polyaxis::test::default_process;
using polyaxis::test::example_machine;

// ded5_ac with 100 mm/s, 60°/s, 1000 mm/s², 3600 °/s² and G64 P0.05.
machine::MachineConfig machine_under_test() {
  machine::MachineConfig m = example_machine("ded5_ac");
  m.feed.linear_max_mm_min = 6000.0;
  m.feed.rotary_max_deg_min = 3600.0;
  m.accel = machine::AccelLimits{1000.0, 3600.0, 0.05};
  return m;
}

TimedBlock line(double dx, double dy, double f_mm_min, BuildTimePart part = BuildTimePart::kTravel) {
  TimedBlock b;
  b.d[0] = std::fabs(dx), b.d[1] = std::fabs(dy);
  const double l = std::hypot(dx, dy);
  b.u_xyz[0] = dx / l, b.u_xyz[1] = dy / l;
  b.feed_per_min = f_mm_min;
  b.part = part;
  return b;
}

double time_of(std::initializer_list<TimedBlock> blocks) {
  BuildTimer t(machine_under_test());
  for (const TimedBlock& b : blocks) t.block(b);
  return t.finish().total_s;
}

TEST(BuildTime, AStraightBlockIsATrapezoid) {
  // 100 mm at 100 mm/s, 1000 mm/s²: 0.1 s up, 0.1 s down (5 mm each), 90 mm at full speed.
  EXPECT_NEAR(time_of({line(100, 0, 6000)}), 1.1, 1e-12);
  // 1 mm cannot reach 100 mm/s: a triangle to √(a·L).
  EXPECT_NEAR(time_of({line(1, 0, 6000)}), 2.0 * std::sqrt(1000.0) / 1000.0, 1e-12);
  // A feed above the machine's maximum is held to it.
  EXPECT_NEAR(time_of({line(100, 0, 60000)}), 1.1, 1e-12);
  // At most the block's length per servo period.
  EXPECT_GE(time_of({line(1e-4, 0, 6000)}), kServoPeriodS);
}

TEST(BuildTime, CollinearBlocksRunThroughAndCornersSlowWithinTheTolerance) {
  const double straight = time_of({line(50, 0, 6000), line(50, 0, 6000)});
  EXPECT_NEAR(straight, 1.1, 1e-9);  // as one 100 mm block
  const double corner = time_of({line(50, 0, 6000), line(0, 50, 6000)});
  // Through the circular blend of the tolerance's radius at √(0.87·a·R), not to a stop.
  const double s = std::sin(3.14159265358979323846 / 4.0);
  const double v = std::sqrt(std::sqrt(0.75) * 1000.0 * 0.05 * s / (1.0 - s));
  const double leg = (100.0 - 0.0) / 1000.0 + (100.0 - v) / 1000.0 + (50.0 - 5.0 - (100.0 * 100.0 - v * v) / 2000.0) / 100.0;
  EXPECT_NEAR(corner, 2.0 * leg, 1e-9);
  EXPECT_GT(corner, straight);
  EXPECT_LT(corner, 1.2);  // two blocks stopping at the corner
  // A reversal stops.
  EXPECT_NEAR(time_of({line(50, 0, 6000), line(-50, 0, 6000)}), 1.2, 1e-9);
  // A wider tolerance rounds the corner faster.
  machine::MachineConfig loose = machine_under_test();
  loose.accel.blend_tolerance_mm = 0.5;
  BuildTimer t(loose);
  t.block(line(50, 0, 6000));
  t.block(line(0, 50, 6000));
  EXPECT_LT(t.finish().total_s, corner);
}

TEST(BuildTime, DwellsStopTheMotionAndCountApart) {
  BuildTimer t(machine_under_test());
  t.block(line(50, 0, 6000, BuildTimePart::kDeposit));
  t.dwell(0.5);
  t.block(line(50, 0, 6000, BuildTimePart::kTravel));
  const BuildTime bt = t.finish();
  EXPECT_NEAR(bt.deposit_s, 0.6, 1e-9);
  EXPECT_NEAR(bt.travel_s, 0.6, 1e-9);
  EXPECT_NEAR(bt.dwell_s, 0.5, 1e-12);
  EXPECT_NEAR(bt.total_s, 1.7, 1e-9);
}

TEST(BuildTime, RotaryBlocksBlendParabolicallyWithHalfTheAcceleration) {
  // 90° of C alone at 3600 °/min: a reorientation, a trapezoid in degrees.
  TimedBlock turn;
  turn.d[4] = 90.0;
  turn.feed_per_min = 3600.0;
  turn.part = BuildTimePart::kReorientation;
  BuildTimer t(machine_under_test());
  t.block(turn);
  const BuildTime alone = t.finish();
  EXPECT_NEAR(alone.reorientation_s, 2.0 * 60.0 / 3600.0 + (90.0 - 60.0 * 60.0 / 3600.0) / 60.0, 1e-9);
  // Two XYZ blocks that also turn C: each at half the acceleration, stopping at its end, the
  // second starting while the first slows: between two stops and no stop at all.
  TimedBlock a = line(50, 0, 3000), b = line(50, 0, 3000);
  a.d[4] = b.d[4] = 5.0;
  const double blended = time_of({a, b});
  const double one_half_accel = 2.0 * 50.0 / 500.0 + (50.0 - 50.0 * 50.0 / 500.0) / 50.0;  // 0→50→0 mm/s at 500 mm/s²
  EXPECT_LT(blended, 2.0 * one_half_accel);
  EXPECT_GT(blended, 2.0 * one_half_accel - 2.0 * 50.0 / 500.0 - 1e-9);
  EXPECT_NEAR(blended, 2.0 * one_half_accel - 50.0 / 500.0, 1e-9);  // one overlap of the full slowing
}

// Through simulate: the parts of a program's time, the process switches stops, the dwell counted.
TEST(BuildTime, AProgramsTimeAndItsParts) {
  const machine::MachineConfig m = machine_under_test();
  const process::ProcessConfig proc = default_process();
  const std::string text = "G21 G90 G94 G17\nG64 P0.0500\nG0 X0 Y0 Z1 A0 C0\nG1 X100 Y0 Z1 A0 C0 F6000\n" + proc.process_on +
                           "\nG4 P0.5000\nG1 X100 Y50 Z1 A0 C0 F3000\n" + proc.process_off +
                           "\nG1 X100 Y50 Z1 A0 C90 F3600\nG1 X0 Y0 Z1 A0 C90 F6000\nM2\n";
  auto r = simulate(m, text, {}, &proc);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const BuildTime& bt = r.value().build_time;
  EXPECT_NEAR(bt.dwell_s, 0.5, 1e-12);
  // 50 mm at 50 mm/s between two stops (the switch and dwell before, the switch after).
  EXPECT_NEAR(bt.deposit_s, 0.05 + 0.05 + 47.5 / 50.0, 1e-9);
  // 90° of C at 60 °/s, at half the acceleration as it blends into the travel after it.
  EXPECT_GT(bt.reorientation_s, 1.45);
  EXPECT_LT(bt.reorientation_s, 2.0 * 60.0 / 1800.0 + 88.0 / 60.0 + 1e-9);
  EXPECT_GT(bt.travel_s, 1.1 + 111.8 / 100.0);  // the first block's trapezoid and the last at half the acceleration
  EXPECT_NEAR(bt.total_s, bt.deposit_s + bt.travel_s + bt.reorientation_s + bt.dwell_s, 1e-12);
  EXPECT_GT(bt.total_s, r.value().feed_time_s);
}

}  // namespace
}  // namespace polyaxis::verify::detail
