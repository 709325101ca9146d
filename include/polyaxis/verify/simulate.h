// Reading our own G-code back: forward kinematics of every block, axis and feed limits, and the
// deviation of the tool from the plan (SPEC §2.7 "Simulate").
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/post/program.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::verify {

// At most this many violation messages are kept (the count is exact).
inline constexpr std::size_t kMaxReportedViolations = 10;

struct AxisSpan {
  double min = INFINITY;  // mm or degrees
  double max = -INFINITY;
  bool empty() const { return !(min <= max); }
};

// What a block of the program is for, in the build time: laying a bead (the process on), moving
// between beads (off, the tool moving), or turning the tool in place (off, only rotary axes move).
enum class BuildTimePart { kDeposit, kTravel, kReorientation };

// The program's time as LinuxCNC's trajectory planner runs it (src/verify/build_time.h: each
// block at the velocity and acceleration its slowest axis allows, blended within the machine's
// G64 P, stopped at dwells and process switches), and its parts. On a robot cell (RAPID) it is the
// programmed feeds' time (the robot controller's planner is not modelled).
struct BuildTime {
  double total_s = 0.0;
  double deposit_s = 0.0;
  double travel_s = 0.0;
  double reorientation_s = 0.0;
  double dwell_s = 0.0;  // G4 dwells (process start and stop)
};

struct SimulationReport {
  std::uint64_t moves = 0;            // G0/G1 blocks that change a position
  std::uint64_t rapid_moves = 0;      // of which G0
  double path_length_mm = 0.0;        // tip path in the part frame, after the first positioning move
  double deposit_length_mm = 0.0;     // of which with the process on (needs the process codes)
  double feed_time_s = 0.0;           // duration of the G1 blocks from their F; rapids not included
  BuildTime build_time;               // the controller's time, with acceleration and blending
  AxisSpan x_mm, y_mm, z_mm, a_or_b_deg, c_deg;  // programmed positions
  std::uint64_t limit_violations = 0; // soft-limit and feed-limit violations
  std::vector<std::string> violations;  // the first kMaxReportedViolations, "line 12: C = ..."
  bool program_end = false;           // M2 or M30 seen
  // With a plan: the largest distance (mm) of the tip, and angle (degrees) of the tool axis, from
  // the nearest planned segment, over every block end and the quarter, half and three-quarter
  // points of every block whose start is known; and the line where the tip deviation is largest.
  bool compared_with_plan = false;
  double max_tip_deviation_mm = 0.0;
  double max_axis_deviation_deg = 0.0;
  std::uint64_t worst_tip_line = 0;
};

// Simulates GCODE (the dialect write_gcode writes: G0 G1 G4 G17 G21 G90 G93 G94, X Y Z A B C F P S
// N words, M-codes, comments in parentheses and after ';') on MACHINE. Axis words are joint
// positions; words absent from the first motion block are 0. On a machine whose post is
// siemens-traori the program is write_traori's instead (post/traori.h): X Y Z the tip and A3 B3 C3
// the tool vector under TRAORI, moved tip-straight with the vector on a great circle, F the tip's
// path feed, G4 F a dwell; the joints for the limits come from polyaxis's inverse kinematics. With PROCESS, blocks equal to its
// process_on / process_off switch the process (for deposit_length_mm). PLAN, when not empty, is
// the program the G-code was written from; each sample is compared with the planned segments in
// order: the earliest segment at or after the last match (a window of 64 segments ahead) that
// holds the sample within PATH_TOLERANCE_MM matches it, so the cost stays linear.
// Errors: kInvalidInput naming the line for malformed or unsupported G-code (G2, G20, G91, a B word
// on an A/C machine, a feed move without F). Limit violations are reported, not errors.
core::Result<SimulationReport> simulate(const machine::MachineConfig& machine, std::string_view gcode,
                                        std::span<const post::ProgramPoint> plan_or_empty,
                                        const process::ProcessConfig* process = nullptr, double path_tolerance_mm = 0.01);

}  // namespace polyaxis::verify
