// The neutral program the toolpath module hands to the post-processors: one point per tool
// position, in the part frame, in the order the machine visits them.
#pragma once

#include <cstdint>
#include <string>

#include "polyaxis/core/vec3.h"

namespace polyaxis::post {

struct ProgramPoint {
  core::Vec3 tip_part_mm;      // nozzle tip, part frame (the rotary table's frame), mm
  core::Vec3 tool_axis_part;   // from the tip up the nozzle, part frame; any length > 0
  double feed_mm_s = 0.0;      // tip speed over the part on the move that arrives here, mm/s (> 0)
  bool process_on = false;     // the move that arrives here deposits (the process is on during it)
  std::uint32_t layer = 0;
  std::uint32_t region = 0;
  // Non-empty on the first point of a block (e.g. "perimeter"): written as the comment
  // "(layer 12 region 0 perimeter)" before the move that arrives here.
  std::string comment_if_new_block;
  // An unwind point: the process is off and the tool is along the table's C axis (vertical in the
  // part frame), where turning C does not move the tool over the part. On a machine that unwinds
  // (machine::unwinds_c) the writer turns C here by whole turns (machine::unwound_c_deg).
  bool c_unwind = false;
};

}  // namespace polyaxis::post
