// A 6-axis industrial robot carrying the torch over a 2-axis positioner that turns the part
// (issue 15, item 2; SPEC §2.7).
//
// The cell. The positioner is a tilt-and-turn table: the machine file's table kinematics
// (xyzac-trt or xyzbc-trt, with its limits.a/b and limits.c and its pivot) describe it exactly as
// they describe a trunnion table, and machine::inverse turns each program point's tool axis up, as
// close as its axes allow. The X Y Z that those kinematics call joints are here the torch tip in the
// positioner's fixed frame (RobotCell::positioner), which the robot carries: limits.x/y/z bound
// it (a safety zone). The robot then holds the torch at that point along the tool axis.
//
// Frames (mm, right-handed). World: the cell's floor frame. RobotCell::base and
// RobotCell::positioner place the robot's base frame and the positioner's fixed frame in the
// world (a translation and a turn about world Z). The part frame turns with the positioner
// (machine/kinematics.h).
//
// The robot is an "ortho-parallel with spherical wrist" arm (Brandstötter, Angerer, Hofbaur 2014,
// "An analytical solution of the inverse kinematics problem of industrial serial manipulators with
// an ortho-parallel basis and a spherical wrist"): the geometry of nearly every industrial 6-axis
// arm (ABB, KUKA, Fanuc, Yaskawa, Stäubli's offsets aside) in seven lengths, with model angles θ:
//
//   wrist centre (base frame):  cx1 = c2·sinθ2 + k·sin(θ2+θ3+ψ) + a1,  cy1 = b,
//                               cz1 = c2·cosθ2 + k·cos(θ2+θ3+ψ),       k = √(a2²+c3²), ψ = atan2(a2, c3)
//                               c = (Rz(θ1)·(cx1, cy1, 0)) + (0, 0, c1 + cz1)
//   flange orientation:         R = Rz(θ1)·Ry(θ2+θ3)·Rz(θ4)·Ry(θ5)·Rz(θ6)
//   flange:                     c + c4·R·ẑ
//
// The controller's joint values q (degrees) relate to the model by θi = signi·qi + zeroi. The
// torch's TCP is a frame on the flange (RAPID tooldata's tframe): its origin at the nozzle tip and
// its z axis pointing out of the torch, toward the work, so the tool axis of polyaxis (from the tip
// up the nozzle) is −z. The turn of the TCP about its z is free for a round nozzle: polyaxis points
// the TCP's x from the tip toward the robot's base axis (horizontally), which keeps the wrist
// near the middle of axes 4 and 6 over the whole work area.
//
// Configuration (ABB confdata [cf1, cf4, cf6, cfx]): cfN = ⌊qN / 90°⌋, the quadrant of axis N;
// cfx = 4·(wrist centre behind axis 1) + 2·(wrist centre behind the lower arm) + (q5 < 0), i.e. the
// shoulder, elbow and wrist branches of the eight solutions.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/machine.h"

namespace polyaxis::machine {

// A rigid frame: origin and unit axes (columns of the rotation), in the parent frame.
struct Frame3 {
  Vec3 origin;
  Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
};

// A unit quaternion (w, x, y, z), RAPID's orient [q1, q2, q3, q4].
struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};

Quaternion quaternion_of(const Frame3& f);       // of f's rotation (Shepperd's method; w ≥ 0)
Frame3 frame_of(Vec3 origin, Quaternion q);      // q need not be normalised

using RobotJoints = std::array<double, 6>;  // q1..q6, degrees, as the controller counts them

struct RobotConfiguration {
  int cf1 = 0, cf4 = 0, cf6 = 0, cfx = 0;
  friend bool operator==(const RobotConfiguration&, const RobotConfiguration&) = default;
};

// The arm's TCP in the world for joints Q. Cost: a few trigonometric calls.
Frame3 robot_tcp_world(const RobotCell& robot, const RobotJoints& q);

// The configuration of joints Q (header comment).
RobotConfiguration robot_configuration(const RobotCell& robot, const RobotJoints& q);

struct RobotSolution {
  RobotJoints q{};
  RobotConfiguration conf;
  double wrist_deg = 0.0;  // |θ5|: 0 at the wrist singularity (axes 4 and 6 in line)
};

// Every joint solution (up to 8) that puts the TCP at TCP_WORLD inside the joint limits, q1, q4 and
// q6 shifted by whole turns to the turn within the limits nearest NEAR (each at 0 without it).
// Empty when the pose is out of reach or every solution leaves a limit. Cost: constant.
std::vector<RobotSolution> robot_solutions(const RobotCell& robot, const Frame3& tcp_world, const RobotJoints* near);

// Why TCP_WORLD has no solution inside the limits: "out of reach: ..." or the first limit each
// branch breaks. For messages.
std::string robot_unreachable_reason(const RobotCell& robot, const Frame3& tcp_world);

// The world TCP the robot must hold for tip TIP_PART and tool axis AXIS_PART (part frame, unit
// or not) with the positioner's rotary axes at POSE's A or B and C (its X Y Z are ignored): z along
// −axis, x toward the robot's base axis (header comment).
Frame3 tcp_world_for(const MachineConfig& machine, const MachinePose& pose, Vec3 tip_part, Vec3 axis_part);

// The tip and the tool axis in the part frame of a world TCP, the positioner at POSE's rotary axes.
MachineToolPose part_tool_of(const MachineConfig& machine, const MachinePose& pose, const Frame3& tcp_world);

// The TCP frame in the part frame (RAPID's robtarget in a work object on the positioner), for a
// world TCP with the positioner at POSE's rotary axes.
Frame3 tcp_in_part(const MachineConfig& machine, const MachinePose& pose, const Frame3& tcp_world);
// Its inverse: the world TCP of a TCP frame given in the part frame.
Frame3 tcp_in_world(const MachineConfig& machine, const MachinePose& pose, const Frame3& tcp_part);

// The joint positions X Y Z (the tip in the positioner's fixed frame) of tip TIP_PART with the
// positioner at POSE's rotary axes: POSE with its X Y Z filled in.
MachinePose positioner_pose_for(const MachineConfig& machine, MachinePose pose, Vec3 tip_part);

}  // namespace polyaxis::machine
