// `polyaxis laminate` as one library call, for the CLI and the Python binding alike: the part (a
// file or a mesh in memory) read and repaired, the waterjet machine and process loaded, the thick
// layers (laminate), their nesting onto sheets (nest_sheets) and one program per sheet
// (sheet_gcode). report::write_lamination_files writes the set.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/lamination/lamination.h"
#include "polyaxis/lamination/outputs.h"
#include "polyaxis/lamination/waterjet.h"
#include "polyaxis/machine/configs.h"
#include "polyaxis/mesh/load_part.h"

namespace polyaxis::lamination {

struct LaminateRequest {
  mesh::LoadOptions part;             // the part's path (or the name of MESH) and how to read and repair it
  std::optional<io::RawMesh> mesh;    // a part in memory, laminated instead of reading part.path
  // --machine, --process, --set: empty paths take the built-in head-head waterjet machine and the
  // abrasive waterjet process (default_waterjet_machine_json, default_waterjet_process_json).
  machine::ConfigSources configs;
  double sheet_w_mm = 300.0, sheet_h_mm = 300.0;  // --sheet-size WxH
  // --sheets (sheets_mm), --area-deviation, --cusp, --subslice, the thread count and the progress
  // callback. max_jet_angle_deg is set from the machine's tilt range.
  LaminateOptions options;
  std::function<void(const std::string&)> on_warning;  // each warning as it is found; may be empty
};

struct LaminateJob {
  mesh::LoadedPart part;
  machine::MachineConfig machine;
  WaterjetProcess process;
  Lamination lamination;
  std::vector<Sheet> sheets;
  std::vector<std::string> programs;  // one per sheet, named by meta.programs
  LaminateMeta meta;
  std::vector<std::string> warnings;  // the part's, then the lamination's (area deviation missed, jet limit, holes left)
};

// Laminates REQUEST. Errors: kUsage (the options, a machine that does not tilt its head, the
// machine and process files), those of reading and repair, of laminate, nest_sheets and sheet_gcode.
core::Result<LaminateJob> run_laminate_job(const LaminateRequest& request);

}  // namespace polyaxis::lamination
