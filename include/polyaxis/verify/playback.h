// Machine playback (SPEC §2.10, issue 15 item 4): the program's moves as the controller reads
// them — each block's end pose in joint values, when it ends on the machine's clock, its line, and
// whether the process is on — for report.html to move the machine along. Read from the G-code
// itself (the same reader as simulate and verify), not from the planner's points.
#pragma once

#include <array>

#include <cstdint>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/process/process.h"

namespace polyaxis::verify {

struct PlaybackFrame {
  machine::MachinePose pose;  // at the end of the block
  double time_s = 0.0;        // when the block ends, from the program's start
  std::uint64_t line = 0;     // the block's line in the G-code (1-based)
  bool process_on = false;    // during the block
  bool rapid = false;         // G0
  std::int64_t layer = -1, region = -1;
  // A robot cell (post abb-rapid): the arm's joints q1..q6 (degrees) at the end of the block.
  bool has_arm = false;
  std::array<float, 6> arm{};
};

// The frames of GCODE on MACHINE: one per motion block and one per dwell (the pose held), in
// program order. Each block ends when the build-time estimate (simulate's build_time, docs/plan.md)
// says: acceleration, blending and the axes' limits as LinuxCNC's trajectory planner; a dwell
// takes its P seconds. The last frame's time is the estimate's total.
// Errors: those of simulate's reader (kInvalidInput naming the line). Cost: linear in the text.
core::Result<std::vector<PlaybackFrame>> playback_frames(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                                         std::string_view gcode);

}  // namespace polyaxis::verify
