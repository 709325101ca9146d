// Siemens Sinumerik programs with TRAORI (issue 15, item 3): the controller does the kinematics.
// Every block gives the tip X Y Z and the tool vector A3 B3 C3 (from the tip up the nozzle, unit)
// in the workpiece frame — the part frame of polyaxis — with ORIWKS and ORIVECT, so the controller
// moves the tip straight and turns the tool vector along a great circle between blocks.
//
//   ; polyaxis: machine ... [kinematics], process ..., post siemens-traori
//   G17 G90 G71 G94
//   TRAORI
//   ORIWKS
//   ORIVECT
//   G0 X.. Y.. Z.. A3=.. B3=.. C3=..
//   ; layer N region R perimeter        (block comments as the LinuxCNC post's, after ';')
//   G1 X.. Y.. Z.. A3=.. B3=.. C3=.. F..
//   G4 F0.5                              (a dwell: F in seconds)
//   TRAFOOF
//   M30
//
// F is the tip's path feed (mm/min, G94), lowered where the machine's axes would otherwise move
// faster than feed.linear_max_mm_min or turn faster than feed.rotary_max_deg_min (solved with
// polyaxis's own inverse kinematics at both ends of the block, which also checks the soft limits:
// a point no branch reaches is kMachineLimit). A move that turns the tool with the tip still is
// written as G0 with the process off; a deposit block the axes would slow below 0.6 of its feed is
// split the same way: the tool turns in place with the process off, then the bead keeps the vector.
// Linear words have 4 decimals, vector components 6.
#pragma once

#include <span>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::post {

// The program for POINTS (as write_gcode's). Errors as write_gcode's: kMachineLimit, kInternal for
// a non-finite value or a feed ≤ 0, kInfeasible for an empty program, kOutput above max_output_bytes.
core::Result<std::string> write_traori(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                       std::span<const ProgramPoint> points, const GcodeOptions& options = {});

// The writer the machine file's "post" chooses (machine::PostDialect), and the file extension of
// its program (".ngc", ".mpf").
core::Result<std::string> write_program(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        std::span<const ProgramPoint> points, const GcodeOptions& options = {});
std::string_view program_extension(const machine::MachineConfig& machine);

}  // namespace polyaxis::post
