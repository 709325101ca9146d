// Subdividing a straight part-frame move whose tool axis turns, so that a controller that
// interpolates every machine axis linearly (G1 with identity kinematics) keeps the tip near the line.
#pragma once

#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/kinematics.h"

namespace polyaxis::machine {

// Pieces are also split until no rotary axis turns more than this per piece (degrees): bounds ΔC
// near the singular tilt (RELIABILITY O2) and keeps the deviation sampling below meaningful.
inline constexpr double kMaxRotaryStepDeg = 5.0;

// A move whose tool axis passes this close (radians) to the singular axis (the tool along C), but
// not through it, is turned through it exactly instead: on the way past, C would have to swing
// half a turn within a sliver of the move (a greedy branch choice cannot even follow it). The
// axis then leaves the slerp path by at most this angle (1°).
inline constexpr double kPoleSnapRad = 1.0 * 3.14159265358979323846 / 180.0;

// Bisection stops here (at most 2^16 pieces per segment); still too far is an error.
inline constexpr int kMaxSubdivisionDepth = 16;

// The poses to program, in order, for the move from (P0, T0) to (P1, T1), starting from START
// (the pose at P0, T0). The tool axis is interpolated by slerp along the segment. Between START and
// the first pose, and between consecutive poses, the tip that forward() gives for the linear
// interpolation of the axes stays within CHORDAL_MM (> 0) of the straight segment P0-P1 (checked
// at a quarter, half and three quarters of each piece) and no rotary axis turns more than
// kMaxRotaryStepDeg. The last pose is the inverse kinematics of (P1, T1). START is not included.
// Errors: those of inverse() for any intermediate point (kMachineLimit), kInfeasible when the tool
// axis reverses (T1 = −T0) or the tolerance cannot be met within kMaxSubdivisionDepth, kMachineLimit
// naming the end stops when that is because C would have to turn past them within the move (the
// same orientation a turn away, or on the other branch, is a jump no piece can make), kUsage for
// a non-positive chordal_mm. An axis path passing within kPoleSnapRad of the singular axis goes
// through it (two moves meeting there, C turned in place between them). Cost: O(pieces)
// inverse/forward evaluations.
core::Result<std::vector<MachinePose>> subdivide(const MachineConfig& machine, Vec3 p0, Vec3 t0, Vec3 p1, Vec3 t1,
                                                 const MachinePose& start, double chordal_mm);

// The poses that turn C from START to TARGET_C_DEG in place: START must have the tool along C (the
// singular axis), where C does not change the tool's orientation over the part; the linear axes
// keep the tip within CHORDAL_MM of where it is, and no piece turns C more than kMaxRotaryStepDeg.
// Empty when C is already there. Errors: kInternal when START is not singular; those of inverse().
core::Result<std::vector<MachinePose>> turn_c_in_place(const MachineConfig& machine, const MachinePose& start, double target_c_deg,
                                                       double chordal_mm);

// Distance (mm) from Q to the segment A-B (to A when A == B).
double distance_to_segment(Vec3 q, Vec3 a, Vec3 b);

}  // namespace polyaxis::machine
