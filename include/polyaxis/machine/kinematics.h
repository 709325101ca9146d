// Forward and inverse kinematics of 3-axis and table-table 5-axis machines (SPEC §2.7).
//
// Frames. The machine frame is fixed to the machine base; the tool is vertical: machine +Z points
// from the nozzle tip up the nozzle. The part frame is fixed to the rotary table; it coincides with
// the machine frame when A (or B) = C = 0. Linear axes X Y Z are joint positions: the tip position
// in the machine frame when the rotary axes are at zero. This is LinuxCNC's trt-kins model, and
// forward() below is exactly the forward map of LinuxCNC's xyzac-trt-kins / xyzbc-trt-kins
// (trtfuncs.c), with s = −1 (LinuxCNC 2.9 default) or +1 (conventional_directions):
//
//   part = rp + Rz(s·C) · ( Rt(s·T) · (joints − rp − d) + d )
//   axis = Rz(s·C) · Rt(s·T) · ẑ
//
// where rp = (x,y,z-rot-point), d = (0, y_offset, z_offset + tool_offset) for A/C (Rt = rotation
// about X) and (x_offset, 0, z_offset + tool_offset) for B/C (Rt = rotation about Y), T is the
// tilt (A or B). G-code carrying these joint values runs on a controller with identity kinematics
// (trivkins, or M429 in LinuxCNC's switchable trt sample configs); with trt-kins active (TCP) the
// controller would instead take the part-frame tip.
//
// Head-head machines ("xyzbc-head", "xyzac-head"): the part is fixed, so the part frame is the
// machine frame (no rotation). The head turns about Z (C) and tilts about its own Y (B) or X (A);
// the tilt and C axes meet at the pivot, L = pivot_length_mm up the tool axis from the tip. X Y Z
// are the tip's position when the head is vertical (the pivot less L·ẑ), as LinuxCNC's 5axiskins
// (whose forward map is exactly this for B/C):
//
//   axis = (−sinB·cosC, −sinB·sinC, cosB)        (B/C: Rz(C)·Ry(−B)·ẑ)
//   axis = ( sinA·sinC, −sinA·cosC, cosA)        (A/C: Rz(C)·Rx(A)·ẑ)
//   tip  = joints + L·(ẑ − axis)
//
// The inverse has the same two branches and the same singularity (tilt 0: C held) as the tables'.
// As on the tables, the G-code carries joint values (trivkins); with 5axiskins active the
// controller would take the tip instead.
//
// Dwivedi (2004) Rules 6-9 are the special case rp = pivot, d = offsets r and h: the orientation
// angles follow from the tool axis components (Rule 6) and the compensating translations are the
// rotated pivot offset (Rule 8); tests/unit/machine/test_kinematics.cpp checks both.
#pragma once

#include <optional>

#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/machine/machine.h"

namespace polyaxis::machine {

using core::Vec3;

// Below this tilt (radians) the rotary axis C is singular (the tool axis is along C, so C does not
// change the orientation): C is held at its previous value (RELIABILITY O2). The tool axis then
// deviates from the request by at most this angle. 1e-6 rad ≈ 0.2 arc-seconds, far below a
// deposition process's angular tolerance.
inline constexpr double kSingularTiltRad = 1e-6;

// A 3-axis machine accepts a requested tool axis only within this angle (radians) of +Z.
inline constexpr double kThreeAxisAxisToleranceRad = 1e-6;

// Axis values may exceed a soft limit by this much (mm or degrees) before it counts as a violation:
// absorbs floating-point round-off of exact limit values (C = 360 unwrapped from 0). Far below
// the 1e-4 resolution of G-code words.
inline constexpr double kAxisLimitSlack = 1e-9;

// One set of axis positions. Units: mm for x_mm y_mm z_mm (joint positions), degrees for the
// rotary words (a_or_b_deg is A on xyzac-trt and xyzac-head, B on xyzbc-trt and xyzbc-head).
// Rotary fields are 0 on 3-axis.
struct MachinePose {
  double x_mm = 0.0;
  double y_mm = 0.0;
  double z_mm = 0.0;
  double a_or_b_deg = 0.0;
  double c_deg = 0.0;
};

// Where the tool is, seen from the part.
struct MachineToolPose {
  Vec3 tip_part_mm;     // nozzle tip, part frame, mm
  Vec3 tool_axis_part;  // unit vector from the tip up the nozzle, part frame
};

// Forward kinematics (formula above). Cost: a few trigonometric calls.
MachineToolPose forward(const MachineConfig& machine, const MachinePose& pose);

// Inverse kinematics: the axis positions that put the nozzle tip at TIP_PART_MM with the tool along
// TOOL_AXIS_PART (any length > 0; it is normalised).
// - Of the two solution branches (T, C) and (−T, C+180°), takes the feasible one with the least
//   rotary motion |ΔT| + |ΔC| from PREVIOUS (from T = C = 0 when PREVIOUS is null).
// - C is unwrapped relative to PREVIOUS (no ±360° jumps); with end stops, the nearest turn
//   (C ± 360°) inside the range is used (RELIABILITY O6).
// - When the tilt is below kSingularTiltRad, C is held at PREVIOUS's value (0 without one) and T is
//   solved for that C (RELIABILITY O2).
// - Linear axes compensate the rotation about the pivot (Dwivedi Rule 8), so the tip lands exactly.
// Errors: kMachineLimit when every branch leaves a soft limit, naming the axis, the value, the limit
// and the whole pose (RELIABILITY O1), or when a 3-axis machine is asked to tilt; kInternal for a
// zero or non-finite input. Cost: constant.
core::Result<MachinePose> inverse(const MachineConfig& machine, Vec3 tip_part_mm, Vec3 tool_axis_part,
                                  const MachinePose* previous);

// Whether inverse(MACHINE, TIP_PART_MM, TOOL_AXIS_PART, nullptr) succeeds, without making its pose
// or its message: for the checks that only ask (the torch guard's many trial axes). Cost: constant.
bool reachable(const MachineConfig& machine, Vec3 tip_part_mm, Vec3 tool_axis_part);

// The linear axes that put the tip at TIP_PART_MM with the rotary axes where ANGLES has them (its
// linear axes are ignored): for fixed rotary axes the tip is an affine map of the linear ones,
// solved exactly. What a controller under tool centre point control (G43.4) does with a block's
// tip and rotary words. nullopt when that map is singular (never on the shipped kinematics).
std::optional<MachinePose> joints_for_tip(const MachineConfig& machine, Vec3 tip_part_mm, const MachinePose& angles);

// The first soft-limit violation of POSE ("C = 400.0000° is beyond its maximum 360°"), or "" when
// POSE is inside every limit (with kAxisLimitSlack).
std::string limit_violation(const MachineConfig& machine, const MachinePose& pose);

// "X12.0000 Y-3.5000 Z40.0000 A15.0000 C90.0000" (rotary words only on 5-axis machines).
std::string format_pose(const MachineConfig& machine, const MachinePose& pose);

}  // namespace polyaxis::machine
