// 5-axis abrasive-waterjet programs for laminated sheets (Hayasi §4): one program per sheet, on a
// head-head machine (the jet tilts over the flat sheet), written by the LinuxCNC post
// (post/gcode.h) so that rs274 reads it and verify reads it back.
//
// Per sheet, pieces in layer order; per piece its holes first, then its outer loop (the piece stays
// held by the sheet until its last cut). Per loop:
// - the jet comes on at a pierce point outside the piece (beyond the outer loop, inside a hole),
//   `lead_in_mm` out along the start sample's normal (in a hole at most 0.45 of the hole's width
//   there), dwells `pierce_s` (the process file's pierce), and leads in to the loop;
// - it runs round the loop once per pass (a convex sample takes its pass's own cut, Hayasi's
//   multi-cut; other samples their one cut on every pass), back to the start;
// - it leads out `lead_out_mm` along the start's normal, goes off, rises `clearance_mm` straight up
//   with the tool turned vertical (an unwind point: C is brought back there) and travels over.
// The jet's centre line is the cut moved out by half the kerf (perpendicular to the line). The
// program's tip is where that line enters the sheet's top face; the tool axis is the line's
// direction up to the head.
//
// Feed (Hayasi Eq. 3, after Limbachiya & Patel), with the jet's path through the sheet as the cut
// depth, h = thickness / cos(tilt):
//   v = π/4 · d0² · R · (1/(1+R))² · p^(3/2) / (μ · di · h) · √(2/ρw)
// in SI units (d0 orifice and di insert diameters, R abrasive-to-water mass flow ratio, p pressure,
// μ the material's specific cutting energy, ρw water's density), clamped to the process's feed range.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/lamination/lamination.h"
#include "polyaxis/lamination/nest.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::lamination {

struct WaterjetProcess {
  std::string name = "awj_steel";
  std::string jet_on = "M64 P0";   // one block of M-codes (process.h's rule: no motion, no program end)
  std::string jet_off = "M65 P0";
  double pierce_s = 1.5;           // dwell with the jet on before it moves
  double kerf_mm = 0.8;            // the cut's width
  double margin_mm = 5.0;          // between pieces' footprints on a sheet (and to its edge)
  double lead_in_mm = 2.0;         // at most half the margin
  double lead_out_mm = 1.0;        // at most half the margin
  double clearance_mm = 10.0;      // travel height above the sheet's top
  double travel_feed_mm_s = 150.0;
  double min_feed_mm_s = 0.2;
  double max_feed_mm_s = 60.0;
  // Eq. 3's coefficients.
  double orifice_mm = 0.33;        // d0
  double insert_mm = 1.02;         // di, the focusing insert
  double abrasive_ratio = 0.2;     // R
  double pressure_mpa = 380.0;     // p
  double specific_energy_gj_m3 = 130.0;  // μ (mild steel)
  double water_density_kg_m3 = 1000.0;   // ρw
};

// The embedded defaults: examples/processes/awj_steel.json (every key spelt out) and
// examples/machines/awj5_head_ac.json (a head-head A/C waterjet, A within ±60°, C endless).
std::string_view default_waterjet_process_json();
std::string_view default_waterjet_machine_json();
// Parses a waterjet process file. kUsage naming the key for anything unknown, missing or out of
// range, and for jet codes that are not a single block of M-codes.
core::Result<WaterjetProcess> parse_waterjet_process(std::string_view json, const std::string& source);

// Eq. 3: the feed (mm/s) through THICKNESS_MM of sheet with the jet TILT_RAD from vertical,
// clamped to the process's range.
double waterjet_feed_mm_s(const WaterjetProcess& process, double thickness_mm, double tilt_rad);

// Where a piece's geometry sits on its sheet, and where the sheet sits on the machine.
struct SheetPiece {
  std::uint32_t layer = 0, piece = 0;
  Placement placement;
};
struct Sheet {
  std::uint32_t index = 0;        // numbered from the thinnest sheets up (the cutting order)
  double thickness_mm = 0.0;
  double size_mm[2] = {0, 0};
  double origin_mm[2] = {0, 0};   // the sheet's corner (0, 0) in the machine's X Y; its bottom lies on Z = 0
  std::vector<SheetPiece> pieces;
  double utilisation = 0.0;       // pieces' reference areas / sheet area
};

// The footprint of PIECE with the kerf: the union of its jet's centre paths at the sheet's bottom
// and top faces (outer ring), what nesting keeps apart.
geom2d::Ring footprint(const Layer& layer, const Piece& piece, double kerf_mm);

// Groups the layers' pieces by thickness and nests each group onto sheets of SIZE_MM (w, h) with
// the process's margin. Sheets come thinnest first. kInfeasible for a piece no sheet holds.
core::Result<std::vector<Sheet>> nest_sheets(const Lamination& lamination, const WaterjetProcess& process, double sheet_w_mm,
                                             double sheet_h_mm, const machine::MachineConfig& machine);

// The program points of SHEET (tip and tool axis in the machine's frame, the jet as the process).
// kUsage when the machine is not head-head.
core::Result<std::vector<post::ProgramPoint>> sheet_program(const Lamination& lamination, const Sheet& sheet, const WaterjetProcess& process,
                                                            const machine::MachineConfig& machine);

// The same points' process as the post takes it: jet codes and pierce dwell.
process::ProcessConfig post_process(const WaterjetProcess& process);

// SHEET's program as LinuxCNC G-code (post/gcode.h): travel as G0, and moves the rotary axes slow
// written slowed with the jet on (GcodeOptions::split_stalls off: no re-pierce, no line swung off
// its cut).
core::Result<std::string> sheet_gcode(const Lamination& lamination, const Sheet& sheet, const WaterjetProcess& process,
                                      const machine::MachineConfig& machine);

}  // namespace polyaxis::lamination
