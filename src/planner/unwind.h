// Unwinding C (issue 11, item 5). Where the tool axis circles the vertical (a torch tilted outward
// around a contour), every loop turns C a whole turn; on a C with end stops the program would run
// into them, and on a continuous C the axis value grows without bound. The planner marks points
// where C can turn back by whole turns without moving the tool over the part: the tool is turned
// upright there (along C, the singular axis) with the process off, and the G-code writer turns C
// (post::ProgramPoint::c_unwind, machine::unwinds_c).
#pragma once

#include <vector>

#include "polyaxis/machine/machine.h"
#include "polyaxis/post/program.h"
#include "polyaxis/slicing/layer.h"

namespace polyaxis::planner::detail {

// The tool axis's winding about the vertical since the last unwind (degrees, summed over the
// axes tilted at least kWindingTiltDeg) after which the next eligible point becomes an unwind.
inline constexpr double kUnwindAfterDeg = 180.0;
// Axes closer to vertical than this do not count toward the winding (C is held there).
inline constexpr double kWindingTiltDeg = 1.0;
// An unwind turns the tool upright in place: only where it is within this of upright, on a layer
// whose build direction is within kUnwindMaxLeanDeg of upright, so the head turns away from the
// layer below and not into it.
inline constexpr double kUnwindMaxTurnDeg = 60.0;
inline constexpr double kUnwindMaxLeanDeg = 20.0;

// PROGRAM with unwind points inserted at process-off points (a retract, a bead's start) where the
// winding since the last one reaches kUnwindAfterDeg: the point again with the tool upright and
// c_unwind set, then, before a bead, the point with its own axis. Unchanged when the machine does
// not unwind. Cost: linear.
std::vector<post::ProgramPoint> insert_c_unwinds(const std::vector<post::ProgramPoint>& program,
                                                 const std::vector<slicing::Layer>& layers, const machine::MachineConfig& machine);

}  // namespace polyaxis::planner::detail
