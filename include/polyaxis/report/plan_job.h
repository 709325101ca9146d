// `polyaxis plan` as one library call, for the CLI and the Python binding alike: the options as the
// command line names them, checked against each other; the part (a file or a mesh in memory) read
// and repaired; the machine and process loaded; planner::plan_part; and the set of files made
// (report/plan_set.h), ready to write with write_plan_files.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/machine/configs.h"
#include "polyaxis/mesh/load_part.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/report/plan_set.h"

namespace polyaxis::report {

struct PlanRequest {
  mesh::LoadOptions part;            // the part's path (or the name of MESH) and how to read and repair it
  std::optional<io::RawMesh> mesh;   // a part in memory, planned instead of reading part.path
  machine::ConfigSources configs;    // --machine, --process, --set
  std::string dir = "0,0,1";         // --dir X,Y,Z: the build direction (single) and the root's default
  std::string strategy = "auto";     // --strategy single|decompose|auto
  bool decompose = false;            // --decompose: the same as strategy "decompose"
  std::string layers = "auto";       // --layers planar|tilted|conformal|auto
  bool no_tilt = false;              // --no-tilt
  std::string root_base;             // --root-base (analysis::parse_root_base)
  std::string substrate;             // --substrate MESH: a part already on the table, read as the part is
  // --perimeters, --threads, --decompose-budget, --allow-collisions, --prebuilt, --path-tolerance-mm
  // (gcode.chordal_mm), --max-output-bytes (gcode.max_output_bytes) and the progress callback. Its
  // strategy, direction, layers, root_base and substrate are set from the fields above.
  planner::PlanPartOptions options;
  // Called with each warning as it is found (the part's and the substrate's before planning, the
  // planner's after), so that a caller can show them before a long plan or a failure. May be empty.
  std::function<void(const std::string&)> on_warning;
};

struct PlanJob {
  mesh::LoadedPart part;                // as read and repaired
  machine::Configs configs;             // the machine and process planned for
  planner::PlanPartResult result;       // the plan, its program, simulation and verification
  PlanMeta meta;                        // report.json's metadata (meta.robot points into result)
  PlanSet set;                          // the set id, the program as written, report.json
  std::vector<std::string> warnings;    // the part's, the substrate's and the planner's, one line each
};

// Plans REQUEST. Errors: kUsage for options that are unknown or contradict each other (naming the
// CLI option, "--layers tilted ... contradicts --no-tilt"), then those of reading and repair
// (naming the file), of the machine and process files, and of planner::plan_part. The job is
// returned by pointer because meta refers into result.
core::Result<std::unique_ptr<PlanJob>> run_plan_job(const PlanRequest& request);

}  // namespace polyaxis::report
