// The build as the machine runs it: a program read back through forward kinematics and checked
// against the physical build model (machine/build_model.h), without the planner's bookkeeping.
//
// Rules (docs/plan.md, "Verification"):
// - Head: at every sample of every move (rapids, approaches and transits included) no point of
//   the head model is below the substrate's or the table's top (build_model.h, conservative).
// - Grounding: a layer is the program's "(layer N region R" block; its normal n is fitted to its
//   deposit samples (the plane they lie on, turned to the tool's side); where the samples stand
//   off that plane by more than the sample spacing (root mean square), the layer is curved (a
//   conformal layer) and n at each sample is its tool axis. A deposit sample p rests on
//   the substrate when it is over the plate and at most ground_mm above its top, or on earlier
//   deposit when a sample q of an earlier layer lies under it: h = (p − q)·n in [0, ground_mm] and
//   |(p − q) − h·n| <= ground_lateral_mm, with
//     ground_mm = max(layer_max, (layer_max + bead)/2) + spacing  (the layer below, or the face of
//                 an earlier region whose bead centres lie half a bead inside it),
//     ground_lateral_mm = max(bead/2, step) + spacing,  step = max(max_step_bead_share·bead,
//                 layer_max·tan α): the bead centre nearest under a point within a layer, or a
//                 contour stepping out by the most a layer may.
// - Material: the head is checked against the material deposited before it. The deposit is kept
//   as samples at most half a bead apart along each bead, each standing for a ball of radius
//   √((bead/2)² + (bead/4)²) ≈ 0.56 bead (a bead is bead wide and at most 0.8 bead high, so the
//   balls along it cover it). Material within
//   kIgnoreBeads bead widths of the tip is not checked: the bead being laid and the beads the tip
//   rests on and against (a nozzle cone of half-angle θ tilted by at most 90° − θ from the layer's
//   normal, as the planner's torch tilts are, does not reach below the tip's layer there). The
//   head is checked every 1.5 bead of tip travel or 1.5° of axis turn and where each move ends;
//   between two checks a head point moves at most the tip's travel plus its distance from the tip
//   times the axis's turn, and half the larger gap on either side is added to the reach; where
//   that finds something, every sample around is checked with its own (smaller) gaps. So the
//   check is conservative by those margins. The nozzle is exact, head boxes are swept about the
//   axis (conservative). A BVH over the deposit samples, each stamped with its place in the
//   deposit order, answers every check that the exact shortcut of detail::BelowTheTip (all the
//   deposit so far low enough under the tip's plane) does not clear.
// - A prebuilt part (machine::PrebuiltBody: --substrate, --prebuilt) is material laid before the
//   program, as balls along its surface (build_model.h) left out only within kIgnorePrebuiltBeads
//   of the tip, and its surface points are ground that a deposit sample rests on by the same rule
//   as earlier deposit.
// - A region starts in mid-air when the first deposit sample of its program is not grounded.
// - Stall: process-on feed time during which the tip moves slower than kStallShare of the
//   process's deposit feed. Dwells after switching on (the process file's dwell_on_s) are counted
//   apart: the process asks for them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/machine/build_model.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::verify {

// A process-on move whose tip speed is below this share of the deposit feed stalls the tip.
inline constexpr double kStallShare = 0.5;
// Head clearance below this (mm) is rounding of the words, not a collision.
inline constexpr double kClearanceSlackMm = 1e-3;
// Material within this many bead widths of the tip is not checked against the head (see above).
inline constexpr double kIgnoreBeads = 3.0;
// A prebuilt part is left out only this near the tip: the bead rests on it, but no bead is laid
// into it.
inline constexpr double kIgnorePrebuiltBeads = 1.5;
// At most this many collisions are listed; all are counted.
inline constexpr std::size_t kMaxListedCollisions = 100;
inline constexpr std::size_t kMaxCollisionPlaces = 20000;

// The head striking something: the plate or the table (body "plate or table"), a prebuilt part
// (kPrebuiltBody), or material laid earlier ("deposit of layer L region R").
inline constexpr const char* kPrebuiltBody = "prebuilt part";
struct Collision {
  std::uint64_t line = 0;  // G-code line of the move
  std::int64_t layer = -1, region = -1;
  core::Vec3 tip;          // the nozzle tip there, part frame
  std::string body;
  double depth_mm = 0.0;   // how far into the body (material: its ball into the head; ≤ 0 within the margin)
};

// The words of a BuildCheck problem for a deposit sample with nothing under it.
inline constexpr std::string_view kUngroundedProblem = "with no earlier deposit";

struct BuildCheck {
  std::uint64_t samples = 0;               // tool positions checked (every move, sampled)
  std::uint64_t head_collisions = 0;       // of which with the head below the plate or the table
  double worst_head_depth_mm = 0.0;        // how far below (≥ 0)
  std::uint64_t worst_head_line = 0;       // the G-code line where it is deepest
  std::uint64_t head_collisions_depositing = 0;  // of head_collisions, with the process on
  std::uint64_t deposit_samples = 0;       // samples on process-on moves
  std::uint64_t ungrounded_samples = 0;    // of which with nothing under them
  std::vector<std::int64_t> mid_air_regions;  // regions whose first deposit is not grounded
  double ground_mm = 0.0;                  // the grounding distances used: along the layer's normal
  double ground_lateral_mm = 0.0;          // and across it
  double process_on_s = 0.0;               // feed time of process-on moves
  double stalled_s = 0.0;                  // of which with the tip below kStallShare of the feed
  double process_on_dwell_s = 0.0;         // dwells with the process on
  std::uint64_t material_collisions = 0;   // samples where the head strikes earlier deposit or a prebuilt part
  std::uint64_t prebuilt_collisions = 0;   // of which the prebuilt part (the first ball found, see below)
  // The deepest strike; once kMaxListedCollisions are found, later samples are counted with the
  // first ball found in reach, so past them this is a lower bound.
  double worst_material_depth_mm = 0.0;
  std::uint64_t material_checks = 0;       // samples checked against the material
  std::uint64_t collisions = 0;            // head_collisions + material_collisions
  std::vector<Collision> collision_list;   // the first kMaxListedCollisions, in program order
  // Where the head struck earlier deposit, or the plate or the table on a layer's moves (the layer
  // and the tip), the first kMaxCollisionPlaces, for the planner to turn the torch there
  // (planner::relieve_collisions).
  std::vector<std::pair<std::uint32_t, core::Vec3>> collision_places;
  std::vector<std::string> first_problems; // up to 10, "line 120 (layer 3 region 0): ..."
};

// Reads GCODE (write_gcode's dialect) on MACHINE and checks it against MODEL. Errors: malformed
// G-code (kInvalidInput, as simulate). Cost: linear in the tip path / sample spacing.
core::Result<BuildCheck> verify_build(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                      const machine::BuildModel& model, std::string_view gcode);

// The clearance of the head at one program point: to the plate or the table, and to the deposit
// laid before it (the process-on moves of PROGRAM before the point, as balls along the beads; the
// material within kIgnoreBeads of the tip left out, as verify_build does). Negative: inside.
struct PointClearance {
  double fixture_mm = 0.0;            // machine::head_clearance_mm, with the tip's own height
  std::optional<double> deposit_mm;   // none when nothing was laid before outside the ignored zone
  std::string deposit_body;           // "deposit of layer L region R"
  std::uint32_t deposit_layer = 0, deposit_region = 0;
  core::Vec3 deposit_point;           // the nearest bead point
};

// PROGRAM is the plan's (table frame); POINT < PROGRAM.size(). Brute force: linear in the deposit
// before the point (meant for `polyaxis explain`, not for whole programs).
PointClearance clearance_at(const machine::BuildModel& model, const std::vector<post::ProgramPoint>& program, std::size_t point,
                            double bead_mm);

}  // namespace polyaxis::verify
