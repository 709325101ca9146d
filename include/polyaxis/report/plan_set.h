// The files of one plan as `polyaxis plan` writes them, for the CLI and the library alike: the
// program stamped with the set id, plan.json, report.json, timings.json, report.html and, when
// asked, one SVG per layer, written as one set (io::OutputSet).
#pragma once

#include <cstdint>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/process/process.h"
#include "polyaxis/report/plan_files.h"

namespace polyaxis::report {

// The metadata of a plan of the part at PART_PATH (any name for a part from memory), with the
// stages' times from JOB and the reading's and repair's (READ_S, REPAIR_S, s). The program's file
// name is the part's stem with the machine's program extension (<stem>.ngc, .mpf, ...).
PlanMeta plan_meta(const planner::PlanPartResult& job, const machine::MachineConfig& machine,
                   const process::ProcessConfig& process, const std::string& part_path, double read_s, double repair_s);

// What is the same in every copy of a plan: the set id (a hash of the program and the report, so
// identical runs give identical files), the program carrying it, and report.json.
struct PlanSet {
  std::string set_id;
  std::string gcode;        // the machine program as written (post::with_set_id)
  std::string report_json;  // report.json, carrying the set id
};

// Stamps META with the set id and makes the set's program and report. Errors: post::with_set_id's.
core::Result<PlanSet> make_plan_set(const planner::PlanPartResult& job, const machine::MachineConfig& machine, PlanMeta& meta);

struct PlanFilesOptions {
  std::string out_dir = "plan";         // made when missing
  bool html = true;                     // report.html (the 3-D viewer and machine playback)
  bool svg = false;                     // layer_NNNNN.svg per layer
  std::uint64_t max_output_bytes = 0;   // refuse a set larger than this (kOutput); 0: no cap
};

// Writes the plan's files as one set: plan.json, report.json, timings.json, report.html, the SVGs,
// and the program last, under OPTIONS.out_dir, all or nothing. kOutput when a file cannot be
// written or the set exceeds max_output_bytes; nothing of this run is then left under the final
// names. Shows progress ("writing") on stderr or the callback in scope.
core::Status write_plan_files(const PlanFilesOptions& options, const PlanSet& set, const planner::PlanPartResult& job,
                              const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanMeta& meta);

}  // namespace polyaxis::report
