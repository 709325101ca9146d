// polyaxis simulate GCODE [--machine M] [--plan PLAN.json] [--json]: reads machine code back
// through forward kinematics. Exit 5 when it breaks a machine limit.
#include <fmt/format.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "config_options.h"
#include "part_options.h"
#include "polyaxis/io/text_file.h"
#include "polyaxis/verify/simulate.h"
#include "polyaxis/report/plan_files.h"
#include "polyaxis/report/plan_view.h"

namespace polyaxis::app {
namespace {

constexpr std::uint64_t kMaxGcodeBytes = 4ull << 30;

struct SimulateOptions {
  std::string gcode_path;
  std::string plan_path;
  ConfigOptions configs;
  bool json = false;
  double path_tolerance_mm = 0.01;
};

int run_simulate(const SimulateOptions& o) {
  auto configs = load_configs(o.configs);
  if (!configs) return report_error(configs.error());
  auto text = io::read_text_file(o.gcode_path, kMaxGcodeBytes);
  if (!text) return report_error(text.error());
  std::vector<post::ProgramPoint> plan;
  if (!o.plan_path.empty()) {
    auto plan_text = io::read_text_file(o.plan_path, kMaxGcodeBytes);
    if (!plan_text) return report_error(plan_text.error());
    auto program = report::read_plan_program(plan_text.value(), o.plan_path);
    if (!program) return report_error(program.error());
    plan = std::move(program.value());
  }
  auto sim = verify::simulate(configs.value().machine, text.value(), plan, &configs.value().process, o.path_tolerance_mm);
  if (!sim) return report_error(sim.error());
  const verify::SimulationReport& r = sim.value();
  if (o.json) {
    std::printf("%s\n", report::simulation_json(r).c_str());
  } else {
    std::printf("%llu moves, path %.1f mm, %.0f s on the controller (%.0f s at the programmed feeds), %llu limit violations",
                static_cast<unsigned long long>(r.moves), r.path_length_mm, r.build_time.total_s, r.feed_time_s,
                static_cast<unsigned long long>(r.limit_violations));
    if (r.compared_with_plan) std::printf(", largest deviation from the plan %.4f mm / %.3f deg", r.max_tip_deviation_mm, r.max_axis_deviation_deg);
    std::printf("\n");
    for (const auto& v : r.violations) std::printf("  %s\n", v.c_str());
  }
  return r.limit_violations > 0 ? static_cast<int>(core::ErrorCode::kMachineLimit) : 0;
}

}  // namespace

Runner add_simulate_command(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Read G-code back through forward kinematics; compare with a plan");
  cmd->add_option("GCODE", o->gcode_path, "the program as polyaxis writes it for the machine's post (G-code, RAPID, a 3MF toolpath package)")->required();
  add_config_options(*cmd, o->configs, false);
  cmd->add_option("--plan", o->plan_path, "plan.json of the same program: report the deviation from it");
  cmd->add_option("--path-tolerance-mm", o->path_tolerance_mm,
                  "A sample of the program this close to a planned segment lies on it (the plan's path tolerance), mm")
      ->capture_default_str()->check(kFinite & CLI::Range(1e-4, 1.0));
  cmd->add_flag("--json", o->json, "Print one JSON object");
  return [o] { return run_simulate(*o); };
}

}  // namespace polyaxis::app
