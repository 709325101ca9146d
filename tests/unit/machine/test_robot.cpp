// The robot cell (machine/robot.h): the ortho-parallel arm's forward map against ABB's published
// calibration pose, its inverse on random poses (every solution, every branch), the configuration
// data, the frames between the robot, the positioner and the part, and the machine file's blocks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "polyaxis/machine/robot.h"

namespace polyaxis::machine {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

MachineConfig cell() {
  auto m = parse_machine(slurp(std::string(POLYAXIS_EXAMPLES_DIR) + "/machines/robot_abb_positioner.json"), "robot");
  EXPECT_TRUE(m.ok()) << m.error().message;
  return m.value();
}

double dist(Vec3 a, Vec3 b) { return norm(a - b); }

// The largest difference between two frames' axes (unitless) and origins (mm).
double frame_gap(const Frame3& a, const Frame3& b) {
  return std::max({dist(a.origin, b.origin), 1e3 * dist(a.x, b.x), 1e3 * dist(a.y, b.y), 1e3 * dist(a.z, b.z)});
}

TEST(Robot, AbbIrb2400AtZeroHasItsFlangeAtTheCalibrationPose) {
  RobotCell r = *cell().robot;
  r.tcp_mm[2] = 0.0;  // tool0: the flange itself
  const Frame3 f = robot_tcp_world(r, {0, 0, 0, 0, 0, 0});
  // ABB's product specification: tool0 at (940, 0, 1455) mm, facing forward, x down.
  EXPECT_NEAR(dist(f.origin, {940.0, 0.0, 1455.0}), 0.0, 1e-9);
  EXPECT_NEAR(dist(f.z, {1, 0, 0}), 0.0, 1e-12);
  EXPECT_NEAR(dist(f.x, {0, 0, -1}), 0.0, 1e-12);
  // Axis 1 turns the arm about the base's z; axis 2 leans it forward; axis 5 turns the flange down.
  EXPECT_NEAR(dist(robot_tcp_world(r, {90, 0, 0, 0, 0, 0}).origin, {0.0, 940.0, 1455.0}), 0.0, 1e-9);
  EXPECT_GT(robot_tcp_world(r, {0, 20, 0, 0, 0, 0}).origin.x, 940.0);
  EXPECT_NEAR(dist(robot_tcp_world(r, {0, 0, 0, 0, 90, 0}).z, {0, 0, -1}), 0.0, 1e-12);
}

TEST(Robot, InverseFindsEveryRandomPoseAndEachSolutionLandsOnIt) {
  const RobotCell r = *cell().robot;
  std::mt19937 rng(7);
  int found = 0;
  for (int i = 0; i < 2000; ++i) {
    RobotJoints q{};
    for (std::size_t k = 0; k < 6; ++k) q[k] = std::uniform_real_distribution<double>(r.min_deg[k], r.max_deg[k])(rng);
    const Frame3 tcp = robot_tcp_world(r, q);
    const auto all = robot_solutions(r, tcp, &q);
    ASSERT_FALSE(all.empty()) << i;
    bool same = false;
    for (const RobotSolution& s : all) {
      EXPECT_LT(frame_gap(robot_tcp_world(r, s.q), tcp), 1e-6) << i;
      double gap = 0.0;
      for (std::size_t k = 0; k < 6; ++k) gap = std::max(gap, std::abs(s.q[k] - q[k]));
      same = same || gap < 1e-6;
      for (std::size_t k = 0; k < 6; ++k) {
        EXPECT_GE(s.q[k], r.min_deg[k] - 1e-9);
        EXPECT_LE(s.q[k], r.max_deg[k] + 1e-9);
      }
    }
    // Away from the wrist singularity the solution the pose came from is among them.
    if (std::abs(q[4]) > 1e-3) {
      EXPECT_TRUE(same) << i;
      found += same ? 1 : 0;
    }
  }
  EXPECT_GT(found, 1900);
}

TEST(Robot, ConfigurationNamesTheShoulderElbowAndWristBranches) {
  const RobotCell r = *cell().robot;
  EXPECT_EQ(robot_configuration(r, {0, 0, 0, 0, 30, 0}), (RobotConfiguration{0, 0, 0, 0}));
  EXPECT_EQ(robot_configuration(r, {0, 0, 0, 0, -30, 0}).cfx, 1);
  EXPECT_EQ(robot_configuration(r, {100, 0, 0, -10, 30, 190}), (RobotConfiguration{1, -1, 2, 0}));
  // The eight solutions of a pose in the middle of the work area differ in cfx.
  RobotCell wide = r;
  for (std::size_t k = 0; k < 6; ++k) wide.min_deg[k] = -400, wide.max_deg[k] = 400;
  const auto all = robot_solutions(wide, robot_tcp_world(wide, {10, 10, 10, 20, 40, 30}), nullptr);
  std::vector<int> cfx;
  for (const RobotSolution& s : all) cfx.push_back(s.conf.cfx);
  std::sort(cfx.begin(), cfx.end());
  EXPECT_EQ(cfx, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(Robot, APoseOutOfReachHasNoSolutionAndSaysWhy) {
  const RobotCell r = *cell().robot;
  Frame3 far;
  far.origin = {4000.0, 0.0, 800.0};
  EXPECT_TRUE(robot_solutions(r, far, nullptr).empty());
  EXPECT_NE(robot_unreachable_reason(r, far).find("reach"), std::string::npos);
  // Behind the robot, reachable only by turning axis 1 past its stops.
  RobotCell narrow = r;
  narrow.min_deg[0] = -90, narrow.max_deg[0] = 90;
  Frame3 behind = robot_tcp_world(r, {170, 10, 10, 0, 60, 0});
  EXPECT_TRUE(robot_solutions(narrow, behind, nullptr).empty());
  EXPECT_NE(robot_unreachable_reason(narrow, behind).find("axis 1"), std::string::npos);
}

TEST(Robot, QuaternionsRoundTrip) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (int i = 0; i < 200; ++i) {
    const Frame3 f = frame_of({1, 2, 3}, {g(rng), g(rng), g(rng), g(rng)});
    EXPECT_NEAR(core::dot(f.x, f.y), 0.0, 1e-12);
    EXPECT_NEAR(dist(core::cross(f.x, f.y), f.z), 0.0, 1e-12);
    EXPECT_LT(frame_gap(frame_of(f.origin, quaternion_of(f)), f), 1e-9);
    EXPECT_GE(quaternion_of(f).w, 0.0);
  }
}

TEST(Robot, TheTorchFollowsThePositionerAndPointsItsXAtTheBase) {
  const MachineConfig m = cell();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    const Vec3 tip{100 * u(rng), 100 * u(rng), 100 + 100 * u(rng)};
    const Vec3 axis = core::normalized(Vec3{u(rng), u(rng), 1.2 + u(rng)});
    auto pose = inverse(m, tip, axis, nullptr);
    ASSERT_TRUE(pose.ok()) << pose.error().message;
    const Frame3 tcp = tcp_world_for(m, pose.value(), tip, axis);
    // The positioner turns the tool axis up: the torch points straight down in the world.
    EXPECT_NEAR(dist(tcp.z, {0, 0, -1}), 0.0, 1e-9);
    EXPECT_NEAR(tcp.x.z, 0.0, 1e-9);
    EXPECT_LT(core::dot(tcp.x, tcp.origin), 0.0);  // toward the base at the origin
    // The robot's tip is the positioner's joints X Y Z in the positioner's frame.
    EXPECT_NEAR(dist(tcp.origin, Vec3{1000, 0, 500} + Vec3{pose.value().x_mm, pose.value().y_mm, pose.value().z_mm}), 0.0, 1e-9);
    const MachinePose again = positioner_pose_for(m, MachinePose{0, 0, 0, pose.value().a_or_b_deg, pose.value().c_deg}, tip);
    EXPECT_NEAR(std::hypot(again.x_mm - pose.value().x_mm, again.y_mm - pose.value().y_mm, again.z_mm - pose.value().z_mm), 0.0, 1e-9);
    const MachineToolPose back = part_tool_of(m, pose.value(), tcp);
    EXPECT_NEAR(dist(back.tip_part_mm, tip), 0.0, 1e-9);
    EXPECT_NEAR(dist(back.tool_axis_part, axis), 0.0, 1e-9);
    EXPECT_LT(frame_gap(tcp_in_world(m, pose.value(), tcp_in_part(m, pose.value(), tcp)), tcp), 1e-9);
    // The arm reaches it, with the wrist well away from its singularity.
    const auto sols = robot_solutions(*m.robot, tcp, nullptr);
    ASSERT_FALSE(sols.empty()) << robot_unreachable_reason(*m.robot, tcp);
  }
}

std::string machine_error(const std::string& text) {
  auto m = parse_machine(text, "cell.json");
  return m.ok() ? std::string() : m.error().message;
}

std::string edited(const std::string& from, const std::string& to, std::string s = "") {
  if (s.empty()) s = slurp(std::string(POLYAXIS_EXAMPLES_DIR) + "/machines/robot_abb_positioner.json");
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

TEST(Robot, TheMachineFileRefusesACellItCannotUse) {
  EXPECT_EQ(machine_error(edited("\"name\"", "\"name\"")), "");
  EXPECT_NE(machine_error(edited("\"post\": \"abb-rapid\",", "")).find("'robot' is only read with \"post\": \"abb-rapid\""), std::string::npos);
  const std::string head = edited("\"pivot\": {\"z_offset_mm\": -80, \"conventional_directions\": true}", "\"pivot\": {\"pivot_length_mm\": 150}",
                                  edited("\"a\": {\"min\"", "\"b\": {\"min\"", edited("\"xyzac-trt\"", "\"xyzbc-head\"")));
  EXPECT_NE(machine_error(head).find("positioner's"), std::string::npos) << machine_error(head);
  EXPECT_NE(machine_error(edited("\"sign\": [1, 1, 1, 1, 1, 1]", "\"sign\": [1, 1, 2, 1, 1, 1]")).find("robot.joints.sign[2]"), std::string::npos);
  EXPECT_NE(machine_error(edited("\"c2\": 705", "\"c2\": 0")).find("robot.geometry_mm.c2"), std::string::npos);
  EXPECT_NE(machine_error(edited("\"unit\": \"STN1\"", "\"unit\": \"ST N1\"")).find("positioner.unit"), std::string::npos);
  EXPECT_NE(machine_error(edited("\"quaternion\": [1, 0, 0, 0]", "\"quaternion\": [0, 0, 0, 0]")).find("robot.tcp.quaternion"), std::string::npos);
  EXPECT_NE(machine_error(edited("\"min_deg\": [-180,", "\"min_deg\": [181,")).find("robot.joints.min_deg[0]"), std::string::npos);
  EXPECT_NE(machine_error(edited("\"wrist_margin_deg\": 5", "\"wrist_margin_deg\": 5, \"reach\": 1")).find("robot.reach"), std::string::npos);
}

}  // namespace
}  // namespace polyaxis::machine
