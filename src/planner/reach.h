// What the machine can reach with the part on its table: the tilt axis's range, and tool axes that
// keep the head clear of the substrate plate and the table (machine/build_model.h), within the
// machine's travel. Private to the
// planner module.
#pragma once

#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/build_model.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/planner/plan.h"
#include "polyaxis/post/program.h"

namespace polyaxis::planner::detail {

// The largest angle (radians) between a tool axis and the table's +Z that the tilt axis reaches:
// the larger end of its range when C turns through a whole turn (either branch then reaches every
// azimuth), else the smaller end; 0 on a 3-axis machine.
double reach_rad(const machine::MachineConfig& machine);

// The largest angle (radians) between a region's build direction and the table's +Z. A table-table
// machine turns the direction up: its tilt reach. A head-head machine leaves the part fixed, so
// gravity does not turn with the region: the process's off_vertical_max_deg, within the tilt reach.
// A 3-axis machine: 0.
double direction_reach_rad(const machine::MachineConfig& machine, const process::ProcessConfig& process);

// The least height (mm) of a tip above the plate's top at which the head keeps CLEARANCE_MM above
// the plate while laying a region built TILT_RAD from the table's +Z: its axis as near upright as
// the layer normal allows (tilted max(0, TILT_RAD − toolpath::kMaxTiltRad)), the tip over the
// plate's middle; 0 where the head clears the plate with the tip on it. The decomposition refuses
// regions that reach lower (analysis::DecomposeOptions::least_height_mm). Cost: one clearance
// evaluation.
double least_layable_height_mm(const machine::MachineConfig& machine, const process::ProcessConfig& process, double tilt_rad,
                               double clearance_mm);

// kMachineLimit naming the first placed region whose build direction is beyond
// direction_reach_rad of +Z, with the tilt it needs, the limit (the tilt axis's, or on a head-head
// machine the process's off_vertical_max_deg) and what would make it reachable.
core::Status check_region_reach(const std::vector<PlanRegion>& placed, const machine::MachineConfig& machine,
                                const process::ProcessConfig& process);

// Turns AXIS (unit) towards the table's +Z, along the great circle, as little as needed for the
// head at TIP, and at TIP + LIFT_MM along the axis (where the tool retracts to), to keep
// CLEARANCE_MM above the plate and the table and for the axis to be within
// REACH_RAD of +Z, but never beyond toolpath::kMaxTiltRad from the layer normal D. Returns false
// (AXIS the best found) when no such axis exists. Cost: about 30 clearance evaluations when the
// axis must turn, one otherwise.
// The machine's soft limits are kept too: an axis for which no inverse-kinematics branch stays
// inside them is turned further.
bool guard_axis(const machine::MachineConfig& machine, const machine::BuildModel& model, double reach_rad, double clearance_mm,
                double lift_mm, Vec3 tip, Vec3 d, Vec3& axis);

// The unit axis at fraction U of the great circle from A to B (unit), evenly in angle: as the
// post interpolates the tool axis between two program points (machine/segment.h), the tip moving
// straight with the same fraction. Opposite axes turn through a perpendicular.
Vec3 axis_between(Vec3 a, Vec3 b, double u);

// True when the head keeps CLEARANCE_MM above the plate and the table all along a move from
// (TIP_FROM, FROM) to (TIP_TO, TO): the tip straight, the axis on the great circle, sampled every
// 2° of turn and every millimetre (and at both ends). Both ends clear do not make the move clear
// where a head circle's disc crosses the plate's edge. Cost: one clearance evaluation per sample.
bool move_clear(const machine::BuildModel& model, double clearance_mm, Vec3 tip_from, Vec3 from, Vec3 tip_to, Vec3 to);

// The largest angle from the table's +Z along the great circle from unit A to unit B (the axis's
// path on a move; not opposite), radians.
double max_tilt_on_arc_rad(Vec3 a, Vec3 b);

// The axes strictly between unit A and unit B, about 1° apart, along which the tool turns from A
// to B with every great-circle step within REACH_RAD of +Z: none when the great circle from A to B
// keeps within it; else the tilt and the azimuth about +Z each interpolated evenly (the path of
// the rotary axes themselves, C the short way round), the tilt held 0.05° inside the reach. Two
// axes below the horizon at distant azimuths need this: the great circle between them dips
// towards −Z.
std::vector<Vec3> axes_within_reach(Vec3 a, Vec3 b, double reach_rad);

// Process-off moves of PROGRAM along which the tool axis would pass beyond REACH_RAD of +Z on its
// great circle turn through axes_within_reach instead, the tip moving evenly along the move (the
// inserted points are copies of the move's end with the tip and the axis between). 0 leaves it.
void keep_travel_within_reach(std::vector<post::ProgramPoint>& program, double reach_rad);

// kMachineLimit naming the first placed region that cannot be reached along its own build
// direction at a corner of its bounding box (table frame): the linear travel, before slicing.
core::Status check_region_travel(const std::vector<PlanRegion>& placed, const machine::MachineConfig& machine);

}  // namespace polyaxis::planner::detail
