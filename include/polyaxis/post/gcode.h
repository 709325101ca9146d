// ISO / LinuxCNC G-code for 3-axis, table-table and head-head 5-axis deposition machines (SPEC §2.7).
//
// The axis words are joint positions (machine/kinematics.h): the program runs on a controller with
// identity kinematics, e.g. trivkins or LinuxCNC's switchable trt configs in identity mode (M429).
// The writer does the inverse kinematics itself and subdivides every move so the tip stays within
// GcodeOptions::chordal_mm of the planned straight segment. Along a move the solution branch and
// the C turn follow the previous pose; where the branch is free (the first point, and a pose with
// the tool along C and the process off) both branches are followed along the program to the next
// such pose and the one that gets further within the limits is taken (C turned in place to it).
// At an unwind point (ProgramPoint::c_unwind) on a machine that unwinds (machine::unwinds_c), C is
// turned in place by whole or half turns so that its sweep to the next unwind point fits the range.
// Deposit moves the rotary axes would make too slow are split into a turn in place with the
// process off and the bead.
//
// Feed (G94, units per minute). LinuxCNC reads F as follows (G-code overview, "Feed Rate"): when any
// of X Y Z moves, F is the XYZ path speed in mm/min and the rotary axes are coordinated to start and
// stop with it; when only rotary axes move, F is in degrees/min along the combined A/B/C motion. The
// writer therefore computes each block's duration in the part frame (tip length / planned feed),
// lengthens it until neither the XYZ speed exceeds feed.linear_max_mm_min nor any rotary axis turns
// faster than feed.rotary_max_deg_min (RELIABILITY O3: slow down, never an F above a limit), and
// writes F = XYZ length / duration, or rotary length / duration for a rotary-only block, rounded
// down. Lengths are those of the words as written (4 decimals), which is what the controller sees.
// Inverse time (G93) is not needed and not written.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/post/program.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::mesh {
struct Mesh;
}

namespace polyaxis::post {

// What the writer did to the feeds (catalogue O3: slowing down is a warning with the count).
struct GcodeStats {
  std::uint64_t feed_blocks = 0;     // G1 blocks
  std::uint64_t linear_limited = 0;  // of which the linear axes' maximum (feed.linear_max_mm_min) set the time
  std::uint64_t rotary_limited = 0;  // of which the rotary axes' maximum set the time (turning the tool)
  // Deposit moves split into a turn in place with the process off and the bead at the new axis
  // (split_stalls): each is a restart of the process, with its dwell.
  std::uint64_t stall_splits = 0;
  // Of which C alone turned at the singular axis, where the torch holds its orientation over the
  // part (the rest turn the torch in place: splits_stall).
  std::uint64_t stall_splits_at_pole = 0;
  // A robot cell (post abb-rapid): what the robot's own inverse kinematics found along the program.
  std::uint64_t robot_targets = 0;          // robtargets written
  std::uint64_t robot_config_changes = 0;   // moves on which the arm changes configuration (cfx): joint moves, process off
  std::uint64_t robot_near_singular = 0;    // targets with the wrist within robot.wrist_margin_deg of its singularity
  double robot_min_wrist_deg = 180.0;       // the smallest |θ5| (0: axes 4 and 6 in line)
  double robot_min_joint_margin_deg = 1e9;  // the smallest distance of any joint to its limits
  double robot_max_joint_step_deg = 0.0;    // the largest turn of one joint between consecutive targets
};

struct GcodeOptions {
  // The part, in the program's (part) frame, for posts that carry it (the 3MF toolpath's object).
  const mesh::Mesh* part = nullptr;
  double chordal_mm = 0.01;            // largest tip deviation from the planned segment between blocks
  bool rapid_travel = false;           // travel moves (process off) as G0 at the controller's rapid rates
                                       // instead of G1 at their planned feed
  // Deposit blocks the rotary axes would slow below their feed are split into a turn in place with
  // the process off and the bead at the new axis (deposition: no metal piles up where the tip
  // crawls). false: they are written slowed, with the process on (cutting: switching a jet off and
  // on re-pierces, and a line swung at the old tip leaves its cut).
  bool split_stalls = true;
  std::uint64_t max_output_bytes = 0;  // 0: no cap; beyond it → kOutput (RELIABILITY O5)
  GcodeStats* stats = nullptr;         // filled when given
};

// The program for POINTS: header (G21 G90 G94 G17 and comments naming machine and process), a G0 to
// the first point (its process_on is ignored: nothing deposits on the way there), then for each
// further point the process on/off codes when its process_on changes (plus G4 P dwell_on_s after
// switching on), a block comment when comment_if_new_block is set, and the G1 (or G0) blocks of the
// subdivided move; process off if still on, then M2. Linear words and rotary words (degrees) have
// 4 decimals; every block carries every axis word; F is written when it changes.
// Errors: kMachineLimit quoting the first move whose pose leaves a soft limit (O1), that a 3-axis
// machine cannot make, that runs C into an end stop, or whose unwind sweep fits no start; kInternal for a non-finite value anywhere (O4) or a feed ≤ 0; kInfeasible
// for an empty program or an unreachable chordal tolerance; kOutput above max_output_bytes.
// Deterministic: the same input gives the same bytes. Cost: linear in the number of blocks.
core::Result<std::string> write_gcode(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                      std::span<const ProgramPoint> points, const GcodeOptions& options = {});

// True when write_gcode (split_stalls; the LinuxCNC post, machine::PostDialect::kLinuxCnc: the
// other posts split by rules of their own) would lay the deposit move from (P0, T0) to (P1, T1) at
// FEED_MM_S as a turn of the tool in place at P0 with the process off, then the bead with T1: the
// rotary or linear axes would hold the tip below the writer's guard share of the feed. The joints
// start from the inverse kinematics of (P0, T0) (either branch turns the axes as far); at the
// singular axis C first turns alone to the move's own, as the writer does (that split holds the
// torch: GcodeStats::stall_splits_at_pole, false here). For the planner's checks, which must see
// every turn of the torch in place that the program makes. False where an end is out of reach
// (the writer reports that move). Cost: O(pieces) inverse/forward evaluations.
bool splits_stall(const machine::MachineConfig& machine, core::Vec3 p0, core::Vec3 t0, core::Vec3 p1, core::Vec3 t1, double feed_mm_s, double chordal_mm = 0.01);

// Writes TEXT to PATH atomically and synced (io::write_file_atomic, Durability::kSynced): no partial
// file on failure (kOutput naming the path).
core::Status save_gcode(const std::string& path, std::string_view text);

}  // namespace polyaxis::post
