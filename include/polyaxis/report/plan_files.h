// report.json, the metrics `polyaxis plan` writes beside the G-code (plan.json: plan_view.h).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
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
};

// report.json: the metrics of SPEC §3 (schema in docs/plan.md). SIM is the simulation of the
// written G-code (build time and path length come from it).
// CHECK, when given, is the program verified against the build model (verify/verify.h).
std::string report_json(const planner::Plan& plan, const verify::SimulationReport& sim, const PlanMeta& meta,
                        const verify::BuildCheck* check = nullptr);

}  // namespace polyaxis::report
