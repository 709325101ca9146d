// polyaxis plan PART [--machine M] [--process P] [--set K=V] [--dir X,Y,Z] [-o DIR]: the main job.
// Writes DIR/<part>.ngc (.mpf for a Siemens TRAORI machine), DIR/plan.json, DIR/report.json (schemas in docs/plan.md), DIR/report.html
// (the 3-D viewer) and, with --svg, one SVG per layer.
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "config_options.h"
#include "part_options.h"
#include "root_base_option.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/report/plan_job.h"

namespace polyaxis::app {
namespace {

struct PlanCommandOptions {
  report::PlanRequest request;
  std::string out_dir = "plan";
  bool json = false;
  bool svg = false;
  bool html = true;
  double chordal_mm = 0.01;
  std::uint64_t max_output_bytes = 0;  // 0: no cap
};

int run_plan(PlanCommandOptions& o) {
  o.request.options.gcode.chordal_mm = o.chordal_mm;
  o.request.options.gcode.max_output_bytes = o.max_output_bytes;
  o.request.on_warning = [](const std::string& w) { std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str()); };
  auto planned = report::run_plan_job(o.request);
  if (!planned) return report_error(planned.error());
  const report::PlanJob& job = *planned.value();
  const planner::Plan& plan = job.result.plan;
  const machine::MachineConfig& machine = job.configs.machine;
  std::fprintf(stderr, "polyaxis: strategy %s: %s\n", planner::strategy_name(job.result.strategy_used), job.result.choice.c_str());

  const report::PlanFilesOptions files{o.out_dir, o.html, o.svg, o.max_output_bytes};
  if (auto s = report::write_plan_files(files, job.set, job.result, machine, job.configs.process, job.meta); !s) return report_error(s.error());
  const std::string stem = std::filesystem::path(o.request.part.path).stem().string();
  if (!job.warnings.empty()) std::fprintf(stderr, "polyaxis: %zu warnings\n", job.warnings.size());
  if (o.json) {
    std::fputs(job.set.report_json.c_str(), stdout);
  } else {
    std::printf("%zu layers, %.0f mm of deposit, build %.0f s, max tilt %.1f deg, %s (unsupported %s mm2) -> %s/%s%s\n",
                plan.layers.layers.size(), plan.deposit_length_mm, job.result.simulation.build_time.total_s, plan.max_tilt_deg,
                plan.unsupported_area_mm2 == 0.0 ? "support-free" : "NOT support-free", planner::area_text(plan.unsupported_area_mm2).c_str(), o.out_dir.c_str(),
                stem.c_str(), std::string(post::program_extension(machine)).c_str());
    if (o.html) std::printf("open %s/report.html in a browser to check the plan\n", o.out_dir.c_str());
  }
  return 0;
}

}  // namespace

Runner add_plan_command(CLI::App& app) {
  auto o = std::make_shared<PlanCommandOptions>();
  o->request.part.repair.check_self_intersections = false;
  CLI::App* cmd = app.add_subcommand("plan", "Plan a part for a machine: layers, toolpaths with tool axes, G-code, report");
  add_part_options(*cmd, o->request.part);
  add_config_options(*cmd, o->request.configs, true);
  cmd->add_option("--dir", o->request.dir, "Build direction X,Y,Z in the part's frame")->capture_default_str();
  cmd->add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
  cmd->add_flag("--no-tilt", o->request.no_tilt, "Keep the torch along the build direction (planar 3-axis deposition)");
  cmd->add_option("--strategy", o->request.strategy,
                  "single: one build direction (--dir); decompose: split the part into regions at the centroidal axis's break links "
                  "(polyaxis analyze), each built along its own direction; auto: one direction, and the decomposition when that is not "
                  "support-free, keeping the better")
      ->capture_default_str()->check(CLI::IsMember({"single", "decompose", "auto"}));
  cmd->add_flag("--decompose", o->request.decompose, "Same as --strategy decompose");
  cmd->add_option("--layers", o->request.layers,
                  "planar: parallel planes along each region's direction (adaptive thickness); tilted: \"3-D\" layers turning with the "
                  "region's centroidal axis, thickness kept in the process's range; conformal: curved layers at even distances from the "
                  "prebuilt part's surface (--substrate or --prebuilt), the torch along the distance's gradient; auto: per region, "
                  "tilted or conformal where they leave less overhang than planar ones")
      ->capture_default_str()->check(CLI::IsMember({"planar", "tilted", "conformal", "auto"}));
  cmd->add_option("--decompose-budget", o->request.options.decompose_budget_facet_visits,
                  "Work a decomposition may do, in facet visits (a few seconds by default); 0: no limit")
      ->capture_default_str()->check(CLI::Range(0.0, 1e15));
  add_root_base_option(*cmd, o->request.root_base);
  cmd->add_option("--substrate", o->request.substrate,
                  "A part already on the table (STL, OBJ, 3MF, STEP or IGES, in the part's frame): it stands on the plate, the part "
                  "less it is deposited onto it (along --dir with --strategy single, each piece along the substrate's normal under "
                  "it with decompose, the better with auto), and the head keeps clear of it");
  cmd->add_option("--prebuilt", o->request.options.prebuilt,
                  "Regions of the decomposition already made (ids as polyaxis analyze lists them; the root, or regions grown from "
                  "prebuilt ones): they stand on the table and the rest is deposited onto them")
      ->delimiter(',');
  cmd->add_option("--perimeters", o->request.options.plan.perimeters, "Perimeters per island")->capture_default_str()->check(CLI::Range(0, 100));
  cmd->add_option("--path-tolerance-mm", o->chordal_mm, "Largest tool-tip deviation from the path between G-code blocks, mm")
      ->capture_default_str()->check(kFinite & CLI::Range(1e-4, 1.0));
  cmd->add_option("--threads", o->request.options.plan.threads, "Worker threads (0: all cores)");
  cmd->add_option("--max-output-bytes", o->max_output_bytes,
                  "Refuse (exit 6, nothing written) when the files of the plan would exceed this many bytes (0: no cap)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e18));
  cmd->add_flag("--allow-collisions", o->request.options.allow_collisions,
                "Write a plan whose program, read back, still strikes the plate, the table or the deposit (exit 0, with a warning)");
  cmd->add_flag("!--keep-directions", o->request.options.redirect_regions,
                "Build every region along the decomposition's direction, even where, read back, the head strikes something no order or "
                "torch tilt clears (by default such regions are tried along other directions first)");
  cmd->add_flag("--json", o->json, "Print report.json instead of one line");
  cmd->add_flag("--svg", o->svg, "Also write one SVG per layer (contours, paths, seams): DIR/layer_NNNNN.svg");
  cmd->add_flag("!--no-html", o->html, "Do not write report.html");
  return [o] { return run_plan(*o); };
}

}  // namespace polyaxis::app
