// Generic ISO G-code with the tip and the rotary axes under tool centre point control (G43.4, as
// Fanuc's TCP, Mazak, Okuma and most ISO controllers call it): X Y Z give the nozzle tip in the
// workpiece frame (polyaxis's part frame) and A/B and C the rotary axes; the controller moves the
// linear axes so that the tip runs straight while the rotary axes turn linearly between blocks.
//
//   %
//   (polyaxis: machine ... [kinematics], process ..., post iso-tcp)
//   (X Y Z: the tip in the workpiece frame, A/B C: the rotary axes; G43.4: the controller keeps the tip)
//   G21 G90 G94 G17
//   G43.4 H1
//   G0 X.. Y.. Z.. A.. C..
//   (layer N region R perimeter)
//   G1 X.. Y.. Z.. A.. C.. F..        (F: the tip's feed over the part, mm/min)
//   G4 X0.5000                        (a dwell, seconds)
//   G49
//   M30
//   %
//
// The rotary words are polyaxis's own inverse kinematics of the tip and the tool axis, which also
// checks the soft limits (kMachineLimit), keeps the solution branch and C's turn along the program,
// and slows F where an axis would pass its maximum. As the rotary axes turn linearly, a block that
// would bend the tool axis more than 0.05° off the great circle between its ends is written in
// pieces along the great circle (a bead whose pieces would stall: the tool turns in place first). A turn with the tip still is a G0 with the
// process off; so is a deposit block whose axes would slow below 0.6 of its feed (post/tool_space.h).
// Linear words have 4 decimals, rotary words 4.
#pragma once

#include <span>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::post {

// The program for POINTS (as write_gcode's). Errors as write_gcode's; kUsage on a 3-axis machine.
core::Result<std::string> write_iso_tcp(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        std::span<const ProgramPoint> points, const GcodeOptions& options = {});

}  // namespace polyaxis::post
