// report.json, the metrics `polyaxis plan` writes beside the G-code (plan.json: plan_view.h).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/program.h"
#include "polyaxis/verify/simulate.h"
#include "polyaxis/verify/verify.h"
#include "polyaxis/planner/plan.h"

namespace polyaxis::report {

struct PlanMeta {
  std::string part;
  std::string machine;   // machine name
  std::string process;   // process name
  std::string gcode;     // the G-code file name
  // Wall-clock seconds of the stages outside make_plan.
  double read_s = 0.0, repair_s = 0.0, gcode_s = 0.0, simulate_s = 0.0, verify_s = 0.0;
  std::string strategy;  // "single" or "decompose": what plan_part chose
  std::string choice;    // and why
  // The output set's id (io/output_set.h): the same in every file of one plan (report.json,
  // plan.json's report, report.html, the G-code's first comment), so that files of two runs are
  // told apart. Empty: not written.
  std::string set_id;
  double choose_s = 0.0;  // planner::PlanPartResult::choose_s
  // A robot cell (machine post abb-rapid): what the robot's inverse kinematics found along the
  // program (report.json "robot"). Null elsewhere.
  const post::GcodeStats* robot = nullptr;
};

// report.json: the metrics of SPEC §3 (schema in docs/plan.md). SIM is the simulation of the
// written G-code (build time and path length come from it).
// CHECK, when given, is the program verified against the build model (verify/verify.h).
// Timings are not in it (timings_json): two identical runs give identical report.json bytes.
std::string report_json(const planner::Plan& plan, const verify::SimulationReport& sim, const PlanMeta& meta,
                        const verify::BuildCheck* check = nullptr);

// timings.json: the set id and the wall-clock seconds of each stage (`timings_s`: read, repair,
// slice, toolpath, program, support, gcode, simulate, verify).
std::string timings_json(const planner::Plan& plan, const PlanMeta& meta);

// `polyaxis simulate --json`: the program read back (moves, lengths, time at the programmed feeds,
// axis ranges, limit violations and, when compared, the largest deviation from the plan).
std::string simulation_json(const verify::SimulationReport& sim);

}  // namespace polyaxis::report
