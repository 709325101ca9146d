// The build verifier (verify/verify.h) and the e2e tests' own read-back (tests/support/readback.h)
// on hand-written programs: each fault found by both, a sound program passed by both.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "polyaxis/post/gcode.h"
#include "polyaxis/verify/verify.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/build_model.h"
#include "support/programs.h"
#include "support/readback.h"

namespace polyaxis::verify {
namespace {

using namespace polyaxis::test;
using post::write_gcode;
using post::GcodeOptions;

struct Bench {
  machine::MachineConfig m = example_machine("ded5_ac");
  process::ProcessConfig p = default_process();
  machine::BuildModel model = machine::make_build_model(m, p, -20, -20, 20, 20);  // plate ±30 mm, top at 0
  polyaxis::test::Plate plate{-30, 30, -30, 30, 0.0, -10.0};

  BuildCheck verify(const std::string& gcode) const {
    auto c = verify_build(m, p, model, gcode);
    EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
    return c.ok() ? c.value() : BuildCheck{};
  }
  polyaxis::test::ReadBack read(const std::string& gcode, bool head_vs_deposit = false) const {
    return polyaxis::test::read_back(m, p, plate, gcode, 1.1, 0.225, head_vs_deposit);
  }
};

// A wall 20 mm long and 24 layers high (0.5 mm each) along X at Y = 0, upright, then MOVE.
std::string wall_then(const std::string& move) {
  std::string g = "G21 G90 G94 G17\n";
  for (int k = 0; k < 24; ++k) {
    const double z = 0.25 + 0.5 * k;
    g += fmt::format("(layer {} region 0 perimeter 0)\nG1 X0 Y0 Z{:.4f} A0 C0 F3000\nM64 P0\nG1 X20 Y0 Z{:.4f} A0 C0 F480\nM65 P0\n", k, z, z);
    g += fmt::format("G1 X20 Y0 Z{:.4f} A0 C0 F3000\n", z + 0.5);
  }
  return g + move + "M2\n";
}

// Two 10 mm beads, one on the other, upright: sound.
const std::string kSound =
    "G21 G90 G94 G17\n(layer 0 region 0 perimeter 0)\nG0 X0 Y0 Z0.3 A0 C0\nM64 P0\nG1 X10 Y0 Z0.3 A0 C0 F480\n"
    "M65 P0\n(layer 1 region 0 perimeter 0)\nG1 X0 Y0 Z0.9 A0 C0 F3000\nM64 P0\nG1 X10 Y0 Z0.9 A0 C0 F480\nM65 P0\nM2\n";

TEST(Verify, TwoBeadsOneOnTheOtherAreSound) {
  const Bench s;
  const BuildCheck c = s.verify(kSound);
  EXPECT_GT(c.deposit_samples, 40u);
  EXPECT_EQ(c.head_collisions, 0u);
  EXPECT_EQ(c.ungrounded_samples, 0u);
  EXPECT_TRUE(c.mid_air_regions.empty());
  EXPECT_NEAR(c.process_on_s, 2.0 * 10.0 / 8.0, 1e-9);
  EXPECT_EQ(c.stalled_s, 0.0);
  const auto rb = s.read(kSound);
  EXPECT_EQ(rb.head_below, 0u);
  EXPECT_EQ(rb.ungrounded, 0u);
  EXPECT_NEAR(rb.on_s, c.process_on_s, 1e-9);
}

// An injected collision: after the wall, a travel crosses it sideways with the upright nozzle's tip
// at half its height, so the cone goes through the wall's upper half. Both the verifier and the
// brute-force read-back find it; passing over the wall's top (the cone clear by 5 mm) they find
// none. This test fails if the head is not checked against the deposit.
TEST(Verify, TheHeadThroughEarlierDepositIsACollision) {
  const Bench s;
  const std::string through = wall_then("(layer 24 region 0 travel)\nG1 X10 Y-20 Z6 A0 C0 F3000\nG1 X10 Y20 Z6 A0 C0 F3000\n");
  const BuildCheck c = s.verify(through);
  EXPECT_GT(c.material_collisions, 0u);
  EXPECT_EQ(c.collisions, c.head_collisions + c.material_collisions);
  EXPECT_GT(c.worst_material_depth_mm, 1.0);  // the cone goes through the wall's top 6 mm
  ASSERT_FALSE(c.collision_list.empty());
  EXPECT_EQ(c.collision_list.front().layer, 24);
  EXPECT_NE(c.collision_list.front().body.find("deposit of layer"), std::string::npos);
  EXPECT_NE(c.first_problems.back().find("strikes the deposit"), std::string::npos);
  EXPECT_GT(s.read(through, true).head_in_deposit, 0u);

  const std::string over = wall_then("(layer 24 region 0 travel)\nG1 X10 Y-20 Z17 A0 C0 F3000\nG1 X10 Y20 Z17 A0 C0 F3000\n");
  const BuildCheck clear = s.verify(over);
  EXPECT_EQ(clear.material_collisions, 0u) << (clear.collision_list.empty() ? "" : clear.collision_list.front().body);
  EXPECT_EQ(s.read(over, true).head_in_deposit, 0u);
  // Laying the wall itself, bead on bead under an upright nozzle, strikes nothing.
  EXPECT_EQ(s.verify(wall_then("")).material_collisions, 0u);
  EXPECT_EQ(s.read(wall_then(""), true).head_in_deposit, 0u);
}

TEST(Verify, ABeadOverNothingAndARegionInMidAir) {
  const Bench s;
  // The second bead is 5 mm up: nothing under it; its region (1) starts there.
  const std::string g =
      "G21 G90 G94 G17\n(layer 0 region 0 perimeter 0)\nG0 X0 Y0 Z0.3 A0 C0\nM64 P0\nG1 X10 Y0 Z0.3 A0 C0 F480\n"
      "M65 P0\n(layer 1 region 1 perimeter 0)\nG1 X0 Y0 Z5.3 A0 C0 F3000\nM64 P0\nG1 X10 Y0 Z5.3 A0 C0 F480\nM65 P0\nM2\n";
  const BuildCheck c = s.verify(g);
  EXPECT_GE(c.ungrounded_samples, 40u);
  ASSERT_EQ(c.mid_air_regions.size(), 1u);
  EXPECT_EQ(c.mid_air_regions[0], 1);
  ASSERT_FALSE(c.first_problems.empty());
  EXPECT_NE(c.first_problems[0].find("region 1"), std::string::npos) << c.first_problems[0];
  const auto rb = s.read(g);
  EXPECT_GE(rb.ungrounded, 40u);
  EXPECT_EQ(rb.regions_starting_in_air.size(), 1u);
  // A bead stepping 1.5 mm sideways over the one below overhangs it by more than the allowed step.
  const std::string step = kSound.substr(0, kSound.size() - 3) +
                           "(layer 2 region 0 perimeter 0)\nG1 X0 Y1.5 Z1.5 A0 C0 F3000\nM64 P0\nG1 X10 Y1.5 Z1.5 A0 C0 F480\nM65 P0\nM2\n";
  const BuildCheck stepped = s.verify(step);
  EXPECT_GE(stepped.ungrounded_samples, 40u);
  EXPECT_TRUE(stepped.mid_air_regions.empty());
  // Stepping 0.45 mm (half a bead, the process's max_step_bead_share) is allowed.
  std::string half = step;
  half.replace(half.find("Y1.5"), 4, "Y0.45");
  half.replace(half.find("Y1.5"), 4, "Y0.45");
  EXPECT_EQ(s.verify(half).ungrounded_samples, 0u);
}

TEST(Verify, AHeadTiltedOverThePlateEntersIt) {
  const Bench s;
  // The tip 1 mm above the middle of the plate, the tool tilted 60°: the cylinder's rim (r 25 at
  // 20 mm up the nozzle) goes 25·sin 60° − 20·cos 60° − 1 = 10.65 mm into the plate.
  const core::Vec3 tip{0, 0, 1}, axis{0, -std::sin(M_PI / 3), std::cos(M_PI / 3)};
  auto pose = machine::inverse(s.m, tip, axis, nullptr);
  ASSERT_TRUE(pose.ok());
  const std::string g = "G21 G90 G94 G17\nG0 " + machine::format_pose(s.m, pose.value()) + "\nM2\n";
  auto c = s.verify(g);
  EXPECT_GT(c.head_collisions, 0u);
  EXPECT_NEAR(c.worst_head_depth_mm, 25.0 * std::sin(M_PI / 3) - 20.0 * 0.5 - 1.0, 1e-3);  // words rounded to 1e-4
  const auto rb = s.read(g);
  EXPECT_GT(rb.head_below, 0u);
  EXPECT_NEAR(rb.worst_head_mm, c.worst_head_depth_mm, 1e-6);
  // Upright at the same height: clear.
  EXPECT_EQ(s.verify("G21 G90 G94 G17\nG0 X0 Y0 Z1 A0 C0\nM2\n").head_collisions, 0u);
  // Outside any layer the strike is no place for the planner to turn the torch; on a layer's move
  // (here its approach, the process off, as on the bumpy bench mesh's decomposition, where one
  // such strike of 0.12 mm threw the whole decomposition away) it is: the layer and the tip.
  EXPECT_TRUE(c.collision_places.empty());
  const auto on_layer = s.verify("G21 G90 G94 G17\n(layer 3 region 1 approach)\nG0 " + machine::format_pose(s.m, pose.value()) + "\nM2\n");
  EXPECT_GT(on_layer.head_collisions, 0u);
  ASSERT_FALSE(on_layer.collision_places.empty());
  EXPECT_EQ(on_layer.collision_places.front().first, 3u);
  EXPECT_LT(core::norm(on_layer.collision_places.front().second - tip), 1e-2);
}

TEST(Verify, TurningWithTheProcessOnStallsTheTip) {
  const Bench s;
  // With the tip on the C axis, C turns 90° at 3600°/min and the tip stays put: 1.5 s with the
  // process on and no bead laid.
  const std::string g =
      "G21 G90 G94 G17\n(layer 0 region 0 perimeter 0)\nG0 X-1 Y0 Z0.3 A0 C0\nM64 P0\nG1 X0 Y0 Z0.3 A0 C0 F480\n"
      "G1 X0 Y0 Z0.3 A0 C90 F3600\nM65 P0\nM2\n";
  const BuildCheck c = s.verify(g);
  EXPECT_NEAR(c.stalled_s, 1.5, 1e-9);
  EXPECT_GT(c.process_on_s, 1.5);
  const auto rb = s.read(g);
  EXPECT_NEAR(rb.slow_s, 1.5, 1e-9);
}

}  // namespace
}  // namespace polyaxis::verify
