// What `polyaxis laminate` writes (schema in docs/laminate.md): lamination.json, one SVG per sheet
// and report.html with the stack of layers in 3-D and the nested sheets in 2-D.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "polyaxis/lamination/lamination.h"
#include "polyaxis/lamination/waterjet.h"

namespace polyaxis::lamination {

struct LaminateMeta {
  std::string part;       // the input's path
  std::string machine;    // machine and process names
  std::string process;
  std::vector<double> sheets_mm;
  double area_deviation = 0.0;
  double max_jet_angle_deg = 0.0;
  double kerf_mm = 0.0;
  std::vector<std::string> programs;  // one file name per sheet
  double seconds = 0.0;               // laminate's own time
  std::vector<std::pair<std::string, double>> stage_seconds;  // read, layers, nesting, programs
};

std::string lamination_json(const Lamination& lamination, const std::vector<Sheet>& sheets, const LaminateMeta& meta);

// SHEET drawn to scale (mm): each piece's footprint (the kerf's outer bound) and reference outline,
// its number "L<layer>.P<piece>" and an arrow for its orientation (the piece's +X), the lead-in of
// each loop and the cut direction.
std::string sheet_svg(const Lamination& lamination, const Sheet& sheet, const WaterjetProcess& process);

// A self-contained page: the figures, a rotatable 3-D wireframe of the stack (every piece's kept
// edge at its layer's bottom and top and the ruled lines between them) and the sheets' SVGs.
std::string lamination_html(const Lamination& lamination, const std::vector<Sheet>& sheets, const WaterjetProcess& process,
                            const LaminateMeta& meta);

}  // namespace polyaxis::lamination
