// The tests' own reading of an ABB RAPID module (post/rapid.h), written apart from the library's
// reader (verify/rapid_walk.cpp): every robtarget taken with a regular expression, placed in the
// world through the positioner's written axes, solved by the robot's inverse kinematics in its
// written configuration, and carried back to the part through the arm's forward kinematics, where
// it must land on the plan's program points.
#pragma once

#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "polyaxis/machine/robot.h"
#include "polyaxis/post/program.h"

namespace polyaxis::test {

struct RapidTarget {
  std::string instr;  // MoveJ, MoveL, ArcLStart, ArcL, ArcLEnd
  core::Vec3 tip;
  machine::Quaternion rot;
  int cfx = 0;
  double eax_a = 0.0, eax_b = 0.0, v_tcp = 0.0;
};

inline std::vector<RapidTarget> rapid_targets(const std::string& text) {
  static const std::regex move(
      R"(^\s*(MoveJ|MoveL|ArcLStart|ArcLEnd|ArcL) \[\[([^\]]+)\],\[([^\]]+)\],\[([^\]]+)\],\[([^\]]+)\]\],\[([^\]]+)\],)");
  auto nums = [](const std::string& s) {
    std::vector<double> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(std::stod(item));
    return v;
  };
  std::vector<RapidTarget> out;
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (!std::regex_search(line, m, move)) continue;
    const auto p = nums(m[2]), q = nums(m[3]), cf = nums(m[4]), ex = nums(m[5]), v = nums(m[6]);
    out.push_back({m[1], {p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]}, static_cast<int>(cf[3]), ex[0], ex[1], v[0]});
  }
  return out;
}

struct RapidReplay {
  std::size_t targets = 0;
  std::size_t unreachable = 0;   // no joint solution in the written configuration
  std::size_t on_plan = 0;       // landing on a program point (in order)
  std::size_t turns = 0;         // the tip on the last target's, the tool turned (a turn in place)
  std::size_t off_plan = 0;      // neither
  double worst_fk_mm = 0.0;      // the arm's forward kinematics against the target, mm
  std::string first_problem;
};

// TOL_MM and TOL_RAD: how far a target may land from its program point.
inline RapidReplay replay_rapid(const machine::MachineConfig& m, const std::string& text, const std::vector<post::ProgramPoint>& plan,
                                double tol_mm = 2e-3, double tol_rad = 1e-4) {
  RapidReplay r;
  std::size_t cursor = 0;
  core::Vec3 last_tip{NAN, NAN, NAN};
  for (const RapidTarget& t : rapid_targets(text)) {
    ++r.targets;
    machine::MachinePose angles{};
    angles.a_or_b_deg = t.eax_a, angles.c_deg = t.eax_b;
    const machine::Frame3 world = machine::tcp_in_world(m, angles, machine::frame_of(t.tip, t.rot));
    const machine::RobotSolution* sol = nullptr;
    const auto sols = machine::robot_solutions(*m.robot, world, nullptr);
    for (const auto& s : sols) {
      if (s.conf.cfx == t.cfx) sol = &s;
    }
    if (sol == nullptr) {
      ++r.unreachable;
      if (r.first_problem.empty()) r.first_problem = "unreachable target " + t.instr;
      continue;
    }
    const machine::Frame3 fk = machine::robot_tcp_world(*m.robot, sol->q);
    r.worst_fk_mm = std::max(r.worst_fk_mm, core::norm(fk.origin - world.origin));
    const machine::MachineToolPose at = machine::part_tool_of(m, angles, fk);
    bool found = false;
    for (std::size_t j = cursor; j < plan.size() && j < cursor + 4; ++j) {
      const core::Vec3 a = core::normalized(plan[j].tool_axis_part);
      if (core::norm(at.tip_part_mm - plan[j].tip_part_mm) <= tol_mm && core::norm(at.tool_axis_part - a) <= tol_rad) {
        cursor = j + 1, found = true;
        break;
      }
    }
    if (found) {
      ++r.on_plan;
    } else if (core::norm(at.tip_part_mm - last_tip) <= tol_mm) {
      ++r.turns;
    } else {
      ++r.off_plan;
      if (r.first_problem.empty()) r.first_problem = "a target off the plan: " + t.instr;
    }
    last_tip = at.tip_part_mm;
  }
  return r;
}

}  // namespace polyaxis::test
