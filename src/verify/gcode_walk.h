// Reading the G-code dialect the machine file's post writes, block by block, for the simulator and
// the build verifier: modal state (G0/G1, G93/G94, F), axis words as joint positions (LinuxCNC),
// the tip and the tool vector A3 B3 C3 under TRAORI (Sinumerik), or the tip and the rotary axes
// under G43.4 (ISO tool centre point control), the process switched by the
// process file's codes, dwells, and the "(layer N region R ...)" or "; layer N region R ..." comments.
#pragma once

#include <charconv>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/robot.h"
#include "polyaxis/process/process.h"

namespace polyaxis::verify::detail {

struct WalkMove {
  std::uint64_t line = 0;
  machine::MachinePose from, to;
  // A Sinumerik TRAORI block: the controller moves the tip straight from TIP_FROM to TIP_TO and
  // turns the tool vector along the great circle from AXIS_FROM to AXIS_TO (unit); FROM and TO are
  // the joints polyaxis's inverse kinematics gives at its ends (for limits, speeds and playback).
  bool tool_space = false;
  core::Vec3 tip_from, tip_to, axis_from, axis_to;
  // An ISO block under G43.4 (post iso-tcp): the tip straight from TIP_FROM to TIP_TO while the
  // rotary axes turn linearly from FROM's to TO's; the tool axis is theirs (not a great circle).
  bool rotary_linear = false;
  // A RAPID MoveJ: the robot's joints turn linearly from Q_FROM to Q_TO (and the positioner's axes
  // from FROM to TO); the TCP follows the arm's forward kinematics, not a straight line.
  bool robot_joint = false;
  machine::RobotJoints q_from{}, q_to{};
  // A RAPID move of any kind: the arm's joints at its end (for the playback's robot).
  std::optional<machine::RobotJoints> arm_to;
  bool from_known = true;   // false for the first motion block: the machine was anywhere
  bool rapid = false;
  double time_min = 0.0;    // as LinuxCNC reads F (G1 only; 0 for rapids and the first move)
  double l_xyz_mm = 0.0, d_tilt_deg = 0.0, d_c_deg = 0.0;
  std::optional<double> f_word;  // the block's own F, if any
  double feed = 0.0;        // the modal feed
  bool inverse_time = false;
  bool process_on = false;
  std::int64_t layer = -1, region = -1;  // from the last "(layer N region R" comment, -1 before one
};

// The tool at fraction U of MV: joint-linear (forward kinematics of the interpolated joints), or
// tip-linear with the axis on the great circle for a tool-space move, or the robot's and the
// positioner's joints interpolated for a RAPID MoveJ.
machine::MachineToolPose tool_at(const machine::MachineConfig& machine, const WalkMove& mv, double u);

struct WalkCallbacks {
  std::function<void(const WalkMove&)> move;                       // every block that moves an axis
  std::function<void(std::uint64_t line, double seconds, bool process_on)> dwell;  // G4 P…
  std::function<void(std::uint64_t line, const machine::MachinePose&, std::string_view)> target;  // every axis block, before limits
};

// Walks GCODE on MACHINE. kInvalidInput naming the line for malformed or unsupported G-code (see
// simulate.h). Sets *PROGRAM_END when M2/M30 is seen (reading stops there).
// The same for an ABB RAPID module (machine post abb-rapid; rapid_walk.cpp): kInvalidInput naming
// the line for what it does not read. walk_gcode hands such machines' programs to it.
core::Status walk_rapid(const machine::MachineConfig& machine, std::string_view text, const process::ProcessConfig* process,
                        const WalkCallbacks& callbacks, bool* program_end);

// The same for a 3MF toolpath package (machine post 3mf-toolpath; toolpath_3mf_walk.cpp): its
// "lines" are the package's poses counted from 1. walk_gcode hands such machines' programs to it.
core::Status walk_toolpath_3mf(const machine::MachineConfig& machine, std::string_view package, const WalkCallbacks& callbacks, bool* program_end);

core::Status walk_gcode(const machine::MachineConfig& machine, std::string_view gcode, const process::ProcessConfig* process,
                        const WalkCallbacks& callbacks, bool* program_end);

// [FIRST, LAST) as a number, exactly as std::from_chars reads it (the same value, end and error);
// the commonest numbers of a program (an optional minus, at most 15 significant digits with at most
// one point) several times faster, as an exact integer over an exact power of ten.
std::from_chars_result read_number(const char* first, const char* last, double& out);

}  // namespace polyaxis::verify::detail
