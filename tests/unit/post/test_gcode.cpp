// G-code writer: grammar, finiteness, limits, feeds, forward kinematics against the plan,
// determinism, and the error cases of RELIABILITY O1, O3, O4, O5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <regex>

#include "polyaxis/post/gcode.h"
#include "polyaxis/verify/simulate.h"
#include "polyaxis/verify/verify.h"
#include "polyaxis/machine/kinematics.h"
#include "support/programs.h"
#include "support/cli.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using namespace polyaxis::test;
using verify::simulate;
using verify::verify_build;
using verify::SimulationReport;

// Words are rounded to 1e-4 mm and 1e-4°; 1e-4° at the ≤ 150 mm these programs reach from the
// pivot is 2.6e-4 mm, so the tip may sit up to ~5e-4 mm beyond the chordal tolerance.
constexpr double kWordRoundingMm = 5e-4;

void check_program(const machine::MachineConfig& m, const std::string& text, const std::vector<ProgramPoint>& plan,
                   double chordal_mm, double max_axis_deviation_deg = 0.5) {
  const process::ProcessConfig proc = default_process();
  const std::string num = R"(-?[0-9]+\.[0-9]{4})";
  const std::string rotary = machine::has_rotary_axes(m.kind)
                                 ? std::string(" ") + machine::tilt_axis_letter(m.kind) + num + " C" + num
                                 : std::string();
  const std::regex grammar("^(\\([^()]*\\)|G21 G90 G94 G17|G64 P[0-9]+\\.[0-9]{4}|G4 P[0-9]+\\.[0-9]{4}|M2|" + proc.process_on + "|" +
                           proc.process_off + "|G0 X" + num + " Y" + num + " Z" + num + rotary + "|G1 X" + num + " Y" +
                           num + " Z" + num + rotary + "( F[0-9]+\\.[0-9]+)?)$");
  const auto lines = lines_of(text);
  ASSERT_GT(lines.size(), 5u);
  for (const std::string& line : lines) {
    EXPECT_TRUE(std::regex_match(line, grammar)) << line;
    std::string lower = line;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    EXPECT_EQ(lower.find("nan"), std::string::npos) << line;
    EXPECT_EQ(lower.find("inf"), std::string::npos) << line;
  }
  EXPECT_EQ(lines.back(), "M2");
  // Every axis word within the soft limits; every F within the linear or rotary maximum.
  for (const Block& b : motion_blocks(text)) {
    const machine::MachinePose pose{b.axes[0], b.axes[1], b.axes[2],
                                   m.kind == machine::Kinematics::kTableTiltB_RotaryC ? b.axes[4] : b.axes[3], b.axes[5]};
    EXPECT_EQ(machine::limit_violation(m, pose), "");
    EXPECT_LE(b.f, std::max(m.feed.linear_max_mm_min, m.feed.rotary_max_deg_min));
  }
  // Forward kinematics of the words follows the plan; the simulator also checks every feed against
  // the axis maxima the way LinuxCNC reads F.
  auto sim = simulate(m, text, plan, &proc);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u) << (sim.value().violations.empty() ? "" : sim.value().violations[0]);
  EXPECT_LE(sim.value().max_tip_deviation_mm, chordal_mm + kWordRoundingMm) << "line " << sim.value().worst_tip_line;
  EXPECT_LE(sim.value().max_axis_deviation_deg, max_axis_deviation_deg);
  EXPECT_TRUE(sim.value().program_end);
  EXPECT_GT(sim.value().deposit_length_mm, 0.0);
}

TEST(Gcode, HelixAndTiltOnEveryMachine) {
  const auto plan = helix_and_tilt();
  for (const char* name : {"ded5_ac", "ded5_bc"}) {
    const machine::MachineConfig m = example_machine(name);
    for (const double chordal : {0.01, 0.002}) {
      auto text = write_gcode(m, default_process(), plan, GcodeOptions{.chordal_mm = chordal});
      ASSERT_TRUE(text.ok()) << name << ": " << text.error().message;
      SCOPED_TRACE(name);
      check_program(m, text.value(), plan, chordal);
      EXPECT_NE(text.value().find("(layer 0 region 0 perimeter)"), std::string::npos);
      EXPECT_NE(text.value().find(std::string("machine ") + name), std::string::npos);
      EXPECT_NE(text.value().find("M64 P0\nG4 P0.5000\n"), std::string::npos);
    }
  }
}

TEST(Gcode, ThreeAxisProgramHasNoRotaryWords) {
  const machine::MachineConfig m = example_machine("gantry3");
  std::vector<ProgramPoint> plan;
  for (int k = 0; k <= 40; ++k) {
    plan.push_back({{100.0 + 50.0 * std::cos(k * 0.2), 100.0 + 50.0 * std::sin(k * 0.2), 1.0 + 0.01 * k},
                    {0.0, 0.0, 1.0},
                    10.0,
                    k > 0,
                    0,
                    0,
                    k == 0 ? "perimeter" : ""});
  }
  auto text = write_gcode(m, default_process(), plan);
  ASSERT_TRUE(text.ok()) << text.error().message;
  check_program(m, text.value(), plan, 0.01);
  EXPECT_EQ(text.value().find(" A"), std::string::npos);
  EXPECT_EQ(text.value().find(" C"), std::string::npos);
}

TEST(Gcode, SameInputSameBytes) {
  const auto plan = helix_and_tilt();
  const machine::MachineConfig m = example_machine("ded5_bc");
  auto a = write_gcode(m, default_process(), plan);
  auto b = write_gcode(m, default_process(), plan);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a.value(), b.value());
}

// The header asks LinuxCNC to blend within the machine's tolerance (G64 P, machine "accel").
TEST(Gcode, HeaderCarriesTheBlendTolerance) {
  machine::MachineConfig m = example_machine("ded5_bc");
  m.accel.blend_tolerance_mm = 0.125;
  auto g = write_gcode(m, default_process(), helix_and_tilt());
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_NE(g.value().find("\nG21 G90 G94 G17\nG64 P0.1250\n"), std::string::npos);
}

TEST(Gcode, SlowMachineGetsLowerFeedsNeverAboveItsLimits) {
  machine::MachineConfig m = example_machine("ded5_ac");
  m.feed.linear_max_mm_min = 200.0;
  m.feed.rotary_max_deg_min = 90.0;
  const auto plan = helix_and_tilt();
  auto text = write_gcode(m, default_process(), plan, GcodeOptions{.rapid_travel = true});
  ASSERT_TRUE(text.ok()) << text.error().message;
  // C cannot keep up with the tip at 1.5 °/s: each bead is laid at its end's axis after a turn in
  // place with the process off, so the axis deviates from the plan by up to one segment's turn.
  double turn_deg = 0.0;
  for (std::size_t i = 1; i < plan.size(); ++i) {
    const core::Vec3 a = core::normalized(plan[i - 1].tool_axis_part), b = core::normalized(plan[i].tool_axis_part);
    if (plan[i].process_on) turn_deg = std::max(turn_deg, std::atan2(core::norm(core::cross(a, b)), core::dot(a, b)) * 180.0 / std::numbers::pi);
  }
  check_program(m, text.value(), plan, 0.01, turn_deg + 0.5);
  EXPECT_NE(text.value().find("turns in place with the process off"), std::string::npos);
  // Read back, the process is never on while the tip crawls for want of rotary speed (this
  // machine's linear limit, 3.3 mm/s, is below the deposit feed itself: that stalls every bead).
  const process::ProcessConfig proc = default_process();
  machine::MachineConfig slow_rotary = example_machine("ded5_ac");
  slow_rotary.feed.rotary_max_deg_min = 90.0;
  auto slow_text = write_gcode(slow_rotary, proc, plan);
  ASSERT_TRUE(slow_text.ok()) << slow_text.error().message;
  auto check = verify_build(slow_rotary, proc, machine::make_build_model(slow_rotary, proc, -50, -50, 50, 50), slow_text.value());
  ASSERT_TRUE(check.ok()) << check.error().message;
  EXPECT_GT(check.value().process_on_s, 0.0);
  EXPECT_EQ(check.value().stalled_s, 0.0);
  EXPECT_EQ(check.value().head_collisions, 0u);
  // Without the split the same moves would stall: the normal machine keeps the feed and does not split.
  auto fast = write_gcode(example_machine("ded5_ac"), proc, plan);
  ASSERT_TRUE(fast.ok());
  EXPECT_EQ(fast.value().find("turns in place"), std::string::npos);
  bool any_rapid = false;
  for (const Block& b : motion_blocks(text.value())) {
    EXPECT_LE(b.f, 200.0);
    any_rapid = any_rapid || b.rapid;
  }
  EXPECT_TRUE(any_rapid);
}

TEST(Gcode, SplitsStallSaysWhichDepositMovesTheWriterTurnsInPlace) {
  // Two-point programs, a process-off start and one deposit move, over tilts from the vertical
  // (the pole, where C turns alone first) to 60°, azimuth changes of 0 to 170°, move lengths of
  // 0.05 to 20 mm, on table-tilt and head-tilt kinematics: post::splits_stall (the planner's view of the
  // writer's rule) says the torch turns in place exactly where the writer turns it so (leaving the
  // pole, C turning alone with the process off holds the torch: not a turn in place).
  const process::ProcessConfig proc = default_process();
  int split = 0, kept = 0;
  for (const char* name : {"ded5_ac", "ded5_bc", "ded5_head_ac"}) {
    const machine::MachineConfig m = example_machine(name);
    for (const double t0 : {0.0, 15.0, 40.0}) {
      for (const double t1 : {0.0, 5.0, 30.0, 60.0}) {
        for (const double dphi : {0.0, 20.0, 90.0, 170.0}) {
          for (const double length : {0.05, 0.8, 5.0, 20.0}) {
            const double d = std::numbers::pi / 180.0;
            const core::Vec3 a{std::sin(t0 * d), 0.0, std::cos(t0 * d)};
            const core::Vec3 b{std::sin(t1 * d) * std::cos(dphi * d), std::sin(t1 * d) * std::sin(dphi * d), std::cos(t1 * d)};
            const core::Vec3 p0{5.0, -3.0, 20.0}, p1 = p0 + core::Vec3{0.6, 0.8, 0.0} * length;
            std::vector<ProgramPoint> points(2);
            points[0].tip_part_mm = p0, points[0].tool_axis_part = a, points[0].feed_mm_s = proc.travel_feed_mm_s;
            points[1].tip_part_mm = p1, points[1].tool_axis_part = b, points[1].feed_mm_s = proc.deposit_feed_mm_s;
            points[1].process_on = true;
            GcodeStats stats;
            auto text = write_gcode(m, proc, points, GcodeOptions{.stats = &stats});
            ASSERT_TRUE(text.ok()) << text.error().message;
            const bool predicted = splits_stall(m, p0, a, p1, b, proc.deposit_feed_mm_s);
            EXPECT_EQ(predicted, stats.stall_splits > stats.stall_splits_at_pole) << name << " tilt " << t0 << " -> " << t1 << " turning " << dphi << " over " << length << " mm";
            (predicted ? split : kept) += 1;
          }
        }
      }
    }
  }
  // Both answers occur.
  EXPECT_GT(split, 20);
  EXPECT_GT(kept, 20);
}

// A bead leaving the vertical whose tilt grows to 40° toward +X, on a B/C machine whose B stops at
// -10°: point by point, the first points' least-motion branch (B = -2°...) runs into the stop
// part-way and would have to jump half a turn of C mid-bead. The branch search leaves the vertical
// on the other branch (B positive, C a half turn round) and the whole bead follows it.
TEST(Gcode, SolutionBranchIsSearchedAlongThePathNotChosenPointByPoint) {
  machine::MachineConfig m = example_machine("ded5_bc");
  m.tilt_deg = {-10.0, 110.0};
  std::vector<ProgramPoint> plan;
  plan.push_back({{20.0, 0.0, 30.0}, {0.0, 0.0, 1.0}, 50.0, false, 0, 0, "approach"});
  plan.push_back({{20.0, 0.0, 5.0}, {0.0, 0.0, 1.0}, 50.0, false, 0, 0, ""});
  for (int k = 1; k <= 40; ++k) {
    const double tilt = k * std::numbers::pi / 180.0;
    plan.push_back({{20.0 + 0.5 * k, 0.0, 5.0}, {std::sin(tilt), 0.0, std::cos(tilt)}, 8.0, true, 0, 0, k == 1 ? "perimeter" : ""});
  }
  auto text = write_gcode(m, default_process(), plan);
  ASSERT_TRUE(text.ok()) << text.error().message;
  check_program(m, text.value(), plan, 0.01);
  double lowest_b = 0.0;
  for (const Block& b : motion_blocks(text.value())) lowest_b = std::min(lowest_b, b.axes[4]);
  EXPECT_GE(lowest_b, -1e-4);
}

// Three loops with the torch tilted outward turn C three whole turns. At the unwind points between
// them (the tool upright, process off) C is turned back: a C with end stops at ±360° builds it, a
// continuous C asked to unwind stays within a turn and a half, and one not asked keeps winding.
TEST(Gcode, CIsUnwoundAtUnwindPoints) {
  std::vector<ProgramPoint> plan;
  constexpr double kTilt = 25.0 * std::numbers::pi / 180.0;
  for (int loop = 0; loop < 3; ++loop) {
    const double z = 2.0 + loop;
    plan.push_back({{40.0, 0.0, z + 5.0}, {0.0, 0.0, 1.0}, 50.0, false, static_cast<std::uint32_t>(loop), 0, "unwind C", true});
    for (int k = 0; k <= 36; ++k) {
      const double az = k * 10.0 * std::numbers::pi / 180.0;
      plan.push_back({{40.0 * std::cos(az), 40.0 * std::sin(az), z},
                      {std::sin(kTilt) * std::cos(az), std::sin(kTilt) * std::sin(az), std::cos(kTilt)},
                      k == 0 ? 50.0 : 8.0, k > 0, static_cast<std::uint32_t>(loop), 0, k == 0 ? "perimeter" : ""});
    }
    plan.push_back({{40.0, 0.0, z + 5.0}, {std::sin(kTilt), 0.0, std::cos(kTilt)}, 50.0, false, static_cast<std::uint32_t>(loop), 0, "retract"});
  }
  auto c_range = [](const std::string& text) {
    double lo = 0.0, hi = 0.0;
    for (const Block& b : motion_blocks(text)) lo = std::min(lo, b.axes[5]), hi = std::max(hi, b.axes[5]);
    return std::pair{lo, hi};
  };
  machine::MachineConfig limited = example_machine("ded5_ac");
  limited.c_continuous = false;
  limited.c_deg = {-360.0, 360.0};
  auto text = write_gcode(limited, default_process(), plan);
  ASSERT_TRUE(text.ok()) << text.error().message;
  check_program(limited, text.value(), plan, 0.01);
  EXPECT_NE(text.value().find("C unwound"), std::string::npos);
  const auto [lo, hi] = c_range(text.value());
  EXPECT_GE(lo, -360.0);
  EXPECT_LE(hi, 360.0);

  machine::MachineConfig unwinding = example_machine("ded5_ac");
  unwinding.c_unwind = true;
  auto unwound = write_gcode(unwinding, default_process(), plan);
  ASSERT_TRUE(unwound.ok()) << unwound.error().message;
  check_program(unwinding, unwound.value(), plan, 0.01);
  const auto [ulo, uhi] = c_range(unwound.value());
  EXPECT_LE(std::max(-ulo, uhi), 540.0);

  auto wound = write_gcode(example_machine("ded5_ac"), default_process(), plan);
  ASSERT_TRUE(wound.ok());
  EXPECT_EQ(wound.value().find("C unwound"), std::string::npos);
  const auto [wlo, whi] = c_range(wound.value());
  EXPECT_GE(std::max(-wlo, whi), 1000.0);

  // End stops too close for a whole loop from where it starts: refused, naming C's range.
  limited.c_deg = {-200.0, 200.0};
  auto refused = write_gcode(limited, default_process(), plan);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, ErrorCode::kMachineLimit);
  EXPECT_NE(refused.error().message.find("C's range"), std::string::npos) << refused.error().message;
}

TEST(Gcode, NonFiniteInputIsAnInternalError) {
  auto plan = helix_and_tilt(10);
  plan[5].tip_part_mm.y = NAN;
  auto r = write_gcode(example_machine("ded5_ac"), default_process(), plan);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kInternal);
  EXPECT_NE(r.error().message.find("point 5"), std::string::npos) << r.error().message;
  plan = helix_and_tilt(10);
  plan[3].feed_mm_s = INFINITY;
  EXPECT_EQ(write_gcode(example_machine("ded5_ac"), default_process(), plan).error().code, ErrorCode::kInternal);
}

TEST(Gcode, FirstMoveBeyondALimitIsQuoted) {
  machine::MachineConfig m = example_machine("ded5_ac");
  m.tilt_deg = {-20.0, 20.0};  // the helix needs up to 30°
  auto r = write_gcode(m, default_process(), helix_and_tilt());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, ErrorCode::kMachineLimit);
  EXPECT_NE(r.error().message.find("move to point"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("A = "), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("pose X"), std::string::npos) << r.error().message;

  auto tilted3 = write_gcode(example_machine("gantry3"), default_process(), helix_and_tilt());
  ASSERT_FALSE(tilted3.ok());
  EXPECT_EQ(tilted3.error().code, ErrorCode::kMachineLimit);
}

TEST(Gcode, EmptyProgramAndOutputCap) {
  EXPECT_EQ(write_gcode(example_machine("ded5_ac"), default_process(), {}).error().code, ErrorCode::kInfeasible);
  auto capped = write_gcode(example_machine("ded5_ac"), default_process(), helix_and_tilt(),
                            GcodeOptions{.max_output_bytes = 2000});
  ASSERT_FALSE(capped.ok());
  EXPECT_EQ(capped.error().code, ErrorCode::kOutput);
}

TEST(Gcode, CommentsCannotEscape) {
  auto plan = helix_and_tilt(4);
  plan[1].comment_if_new_block = "wall (outer); M2\nG0 X0";
  auto text = write_gcode(example_machine("ded5_ac"), default_process(), plan);
  ASSERT_TRUE(text.ok());
  EXPECT_NE(text.value().find("(layer 0 region 0 wall [outer], M2?G0 X0)"), std::string::npos) << text.value();
}

TEST(Gcode, SaveIsAtomic) {
  polyaxis::test::TempDir dir;
  const std::string path = (dir / "out.ngc").string();
  ASSERT_TRUE(save_gcode(path, "G21\nM2\n").ok());
  EXPECT_EQ(polyaxis::test::slurp(path), "G21\nM2\n");
  auto bad = save_gcode((dir / "missing" / "out.ngc").string(), "M2\n");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kOutput);
}

}  // namespace
}  // namespace polyaxis::post
