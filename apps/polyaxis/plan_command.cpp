// polyaxis plan PART [--machine M] [--process P] [--set K=V] [--dir X,Y,Z] [-o DIR]: the main job.
// Writes DIR/<part>.ngc (.mpf for a Siemens TRAORI machine), DIR/plan.json, DIR/report.json (schemas in docs/plan.md), DIR/report.html
// (the 3-D viewer) and, with --svg, one SVG per layer.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.h"
#include "config_options.h"
#include "part_options.h"
#include "root_base_option.h"
#include "polyaxis/core/progress.h"
#include "polyaxis/io/output_set.h"
#include "polyaxis/io/write_file.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/report/layers.h"
#include "polyaxis/report/plan_files.h"
#include "polyaxis/report/plan_view.h"
#include "polyaxis/report/report_html.h"

namespace polyaxis::app {
namespace {

struct PlanCommandOptions {
  PartOptions part;
  ConfigOptions configs;
  std::string dir = "0,0,1";
  std::string out_dir = "plan";
  bool no_tilt = false;
  bool decompose = false;
  std::string strategy = "auto";
  std::string layers = "auto";
  planner::PlanPartOptions part_plan;
  std::string root_base;
  std::string substrate;  // --substrate MESH
  bool json = false;
  bool svg = false;
  bool html = true;
  double chordal_mm = 0.01;
  std::uint64_t max_output_bytes = 0;  // 0: no cap
};

core::Status parse_direction(const std::string& text, core::Vec3& out) {
  std::stringstream s(text);
  std::string item;
  int i = 0;
  while (std::getline(s, item, ',')) {
    if (i >= 3) break;
    try {
      std::size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument(item);
      out[i++] = v;
    } catch (const std::exception&) {
      return core::make_error(core::ErrorCode::kUsage, fmt::format("--dir: '{}' is not a finite number", item));
    }
  }
  if (i != 3) return core::make_error(core::ErrorCode::kUsage, fmt::format("--dir: expected X,Y,Z, got '{}'", text));
  return {};
}

// The output set's id: a hash of the program and the report (without the id), so that identical
// runs give identical files and any two different sets differ.
std::string set_id(std::string_view gcode, std::string_view report) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a, 64 bits
  for (const std::string_view part : {gcode, report}) {
    for (const char c : part) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

// Writes the plan's files as one set (io::OutputSet): plan.json, report.json (also returned in
// REPORT_TEXT, for --json), timings.json, report.html, the SVGs, and the G-code last, each carrying
// the set id (set in META). kOutput when a file cannot be written or the set exceeds
// --max-output-bytes; nothing is then left under the final names.
core::Status write_plan_set(const PlanCommandOptions& o, const planner::PlanPartResult& job, const machine::MachineConfig& machine,
                            const process::ProcessConfig& process, report::PlanMeta& meta, std::string& report_text) {
  auto set = io::OutputSet::open(o.out_dir);
  if (!set) return set.error();
  const planner::Plan& plan = job.plan;
  const std::string stem = std::filesystem::path(o.part.path).stem().string();
  meta.set_id = set_id(job.gcode, report::report_json(plan, job.simulation, meta, &job.check));
  auto stamped = post::with_set_id(machine, job.gcode, meta.set_id);
  if (!stamped) return stamped.error();
  const std::string& gcode = stamped.value();
  report_text = report::report_json(plan, job.simulation, meta, &job.check);
  const std::size_t files = 4 + (o.html ? 1 : 0) + (o.svg ? plan.layers.layers.size() : 0);
  core::Progress progress("writing", files);
  std::size_t written = 0;
  std::uint64_t total = 0;
  auto add = [&](const std::string& name, std::string_view bytes, io::Durability durability) -> core::Status {
    total += bytes.size();
    if (o.max_output_bytes != 0 && total > o.max_output_bytes) {
      return core::make_error(core::ErrorCode::kOutput, fmt::format("{}/{}: the output exceeds --max-output-bytes {} ({} bytes so far); "
                                                                    "nothing of this run was written",
                                                                    o.out_dir, name, o.max_output_bytes, total));
    }
    auto s = set.value().add(name, bytes, durability);
    if (s) progress.update(++written);
    return s;
  };
  report::PlanView view =
      report::make_plan_view(plan, machine, process, job.axis ? &*job.axis : nullptr, o.part.path, report_text, &job.check);
  if (o.html) {
    // Machine playback in report.html: the program as its controller reads it.
    auto frames = verify::playback_frames(machine, process, job.gcode);
    if (!frames) return frames.error();
    view.playback = report::ViewPlayback{machine, std::move(frames.value())};
  }
  if (auto s = add("plan.json", report::plan_view_json(view), io::Durability::kAtomic); !s) return s;
  if (auto s = add("report.json", report_text, io::Durability::kAtomic); !s) return s;
  if (auto s = add("timings.json", report::timings_json(plan, meta), io::Durability::kAtomic); !s) return s;
  if (o.html) {
    if (auto s = add("report.html", report::report_html(view, report::viewer_bundle()), io::Durability::kAtomic); !s) return s;
  }
  if (o.svg) {
    for (std::size_t k = 0; k < plan.layers.layers.size(); ++k) {
      const std::string name = fmt::format("layer_{:05d}.svg", plan.layers.layers[k].index);
      if (auto s = add(name, report::layer_svg(plan.layers.layers[k], &plan.toolpaths[k]), io::Durability::kAtomic); !s) return s;
    }
  }
  // The machine program last: moved into place after everything it belongs with.
  if (auto s = add(stem + std::string(post::program_extension(machine)), gcode, io::Durability::kSynced); !s) return s;
  return set.value().commit();
}

int run_plan(PlanCommandOptions& o) {
  planner::PlanPartOptions& opt = o.part_plan;
  if (auto s = parse_direction(o.dir, opt.direction); !s) return report_error(s.error());
  opt.plan.tilt_on_overhang = !o.no_tilt;
  opt.gcode.chordal_mm = o.chordal_mm;
  opt.gcode.max_output_bytes = o.max_output_bytes;
  if (o.decompose) {
    if (o.strategy != "auto" && o.strategy != "decompose") {
      return report_error(core::make_error(core::ErrorCode::kUsage, "--decompose is --strategy decompose; it contradicts --strategy " + o.strategy));
    }
    o.strategy = "decompose";
  }
  opt.plan.layers = o.layers == "planar" ? planner::LayerChoice::kPlanar
                    : o.layers == "tilted"    ? planner::LayerChoice::kTilted
                    : o.layers == "conformal" ? planner::LayerChoice::kConformal
                                              : planner::LayerChoice::kAuto;
  if (o.no_tilt && (opt.plan.layers == planner::LayerChoice::kTilted || opt.plan.layers == planner::LayerChoice::kConformal)) {
    return report_error(core::make_error(core::ErrorCode::kUsage, fmt::format("--layers {} turns the torch with each layer; it contradicts --no-tilt", o.layers)));
  }
  opt.strategy = o.strategy == "single" ? planner::Strategy::kSingle
                 : o.strategy == "decompose" ? planner::Strategy::kDecompose : planner::Strategy::kAuto;
  if (!o.root_base.empty() && opt.strategy == planner::Strategy::kSingle) {
    return report_error(core::make_error(core::ErrorCode::kUsage, "--root-base places the root region: it needs --strategy decompose or auto"));
  }
  auto root_base = parse_root_base(o.root_base);
  if (!root_base) return report_error(root_base.error());
  opt.root_base = root_base.value();
  auto configs = load_configs(o.configs);
  if (!configs) return report_error(configs.error());
  const machine::MachineConfig& machine = configs.value().machine;
  const process::ProcessConfig& process = configs.value().process;
  if (opt.plan.layers == planner::LayerChoice::kConformal && o.substrate.empty() && opt.prebuilt.empty()) {
    return report_error(core::make_error(core::ErrorCode::kUsage,
                                         "--layers conformal: the layers follow a prebuilt part's surface; give one with --substrate or --prebuilt"));
  }
  if (!o.substrate.empty() && !opt.prebuilt.empty()) {
    return report_error(core::make_error(core::ErrorCode::kUsage, "--substrate gives the prebuilt part as its own mesh; it contradicts --prebuilt"));
  }
  if (!opt.prebuilt.empty() && opt.strategy == planner::Strategy::kSingle) {
    return report_error(core::make_error(core::ErrorCode::kUsage, "--prebuilt names regions of the decomposition; it contradicts --strategy single"));
  }
  auto loaded = load_part(o.part);
  if (!loaded) return report_error(loaded.error());
  std::size_t warnings = 0;
  for (const auto& w : loaded.value().warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str()), ++warnings;
  if (!o.substrate.empty()) {
    // Read and repaired as the part is, in its units (--scale).
    PartOptions substrate = o.part;
    substrate.path = o.substrate;
    auto base = load_part(substrate);
    if (!base) {
      core::Error e = base.error();
      e.message = "--substrate: " + e.message;
      return report_error(e);
    }
    for (const auto& w : base.value().warnings) std::fprintf(stderr, "polyaxis: warning: --substrate: %s\n", w.c_str()), ++warnings;
    opt.substrate = std::move(base.value().repaired.mesh);
  }

  auto result = planner::plan_part(loaded.value().repaired, machine, process, opt);
  if (!result) return report_error(result.error());
  const planner::PlanPartResult& job = result.value();
  const planner::Plan& plan = job.plan;
  std::fprintf(stderr, "polyaxis: strategy %s: %s\n", planner::strategy_name(job.strategy_used), job.choice.c_str());
  for (const std::string& w : job.warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str()), ++warnings;

  const std::string stem = std::filesystem::path(o.part.path).stem().string();
  report::PlanMeta meta{o.part.path, machine.name, process.name, stem + std::string(post::program_extension(machine)), loaded.value().read_s, loaded.value().repair_s,
                        job.gcode_s, job.simulate_s, job.verify_s, "", "", ""};
  meta.strategy = planner::strategy_name(job.strategy_used);
  meta.choose_s = job.choose_s;
  meta.choice = job.choice;
  if (machine.robot) meta.robot = &job.gcode_stats;
  std::string report_text;
  if (auto s = write_plan_set(o, job, machine, process, meta, report_text); !s) return report_error(s.error());
  if (warnings > 0) std::fprintf(stderr, "polyaxis: %zu warnings\n", warnings);
  if (o.json) {
    std::fputs(report_text.c_str(), stdout);
  } else {
    std::printf("%zu layers, %.0f mm of deposit, build %.0f s, max tilt %.1f deg, %s (unsupported %s mm2) -> %s/%s%s\n",
                plan.layers.layers.size(), plan.deposit_length_mm, job.simulation.feed_time_s, plan.max_tilt_deg,
                plan.unsupported_area_mm2 == 0.0 ? "support-free" : "NOT support-free", planner::area_text(plan.unsupported_area_mm2).c_str(), o.out_dir.c_str(),
                stem.c_str(), std::string(post::program_extension(machine)).c_str());
    if (o.html) std::printf("open %s/report.html in a browser to check the plan\n", o.out_dir.c_str());
  }
  return 0;
}

}  // namespace

Runner add_plan_command(CLI::App& app) {
  auto o = std::make_shared<PlanCommandOptions>();
  o->part.repair.check_self_intersections = false;
  CLI::App* cmd = app.add_subcommand("plan", "Plan a part for a machine: layers, toolpaths with tool axes, G-code, report");
  add_part_options(*cmd, o->part);
  add_config_options(*cmd, o->configs, true);
  cmd->add_option("--dir", o->dir, "Build direction X,Y,Z in the part's frame")->capture_default_str();
  cmd->add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
  cmd->add_flag("--no-tilt", o->no_tilt, "Keep the torch along the build direction (planar 3-axis deposition)");
  cmd->add_option("--strategy", o->strategy,
                  "single: one build direction (--dir); decompose: split the part into regions at the centroidal axis's break links "
                  "(polyaxis analyze), each built along its own direction; auto: one direction, and the decomposition when that is not "
                  "support-free, keeping the better")
      ->capture_default_str()->check(CLI::IsMember({"single", "decompose", "auto"}));
  cmd->add_flag("--decompose", o->decompose, "Same as --strategy decompose");
  cmd->add_option("--layers", o->layers,
                  "planar: parallel planes along each region's direction (adaptive thickness); tilted: \"3-D\" layers turning with the "
                  "region's centroidal axis, thickness kept in the process's range; conformal: curved layers at even distances from the "
                  "prebuilt part's surface (--substrate or --prebuilt), the torch along the distance's gradient; auto: per region, "
                  "tilted or conformal where they leave less overhang than planar ones")
      ->capture_default_str()->check(CLI::IsMember({"planar", "tilted", "conformal", "auto"}));
  cmd->add_option("--decompose-budget", o->part_plan.decompose_budget_facet_visits,
                  "Work a decomposition may do, in facet visits (a few seconds by default); 0: no limit")
      ->capture_default_str()->check(CLI::Range(0.0, 1e15));
  add_root_base_option(*cmd, o->root_base);
  cmd->add_option("--substrate", o->substrate,
                  "A part already on the table (STL, OBJ, 3MF, STEP or IGES, in the part's frame): it stands on the plate, the part "
                  "less it is deposited onto it (along --dir with --strategy single, each piece along the substrate's normal under "
                  "it with decompose, the better with auto), and the head keeps clear of it");
  cmd->add_option("--prebuilt", o->part_plan.prebuilt,
                  "Regions of the decomposition already made (ids as polyaxis analyze lists them; the root, or regions grown from "
                  "prebuilt ones): they stand on the table and the rest is deposited onto them")
      ->delimiter(',');
  cmd->add_option("--perimeters", o->part_plan.plan.perimeters, "Perimeters per island")->capture_default_str()->check(CLI::Range(0, 100));
  cmd->add_option("--path-tolerance-mm", o->chordal_mm, "Largest tool-tip deviation from the path between G-code blocks, mm")
      ->capture_default_str()->check(kFinite & CLI::Range(1e-4, 1.0));
  cmd->add_option("--threads", o->part_plan.plan.threads, "Worker threads (0: all cores)");
  cmd->add_option("--max-output-bytes", o->max_output_bytes,
                  "Refuse (exit 6, nothing written) when the files of the plan would exceed this many bytes (0: no cap)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e18));
  cmd->add_flag("--allow-collisions", o->part_plan.allow_collisions,
                "Write a plan whose program, read back, still strikes the plate, the table or the deposit (exit 0, with a warning)");
  cmd->add_flag("--json", o->json, "Print report.json instead of one line");
  cmd->add_flag("--svg", o->svg, "Also write one SVG per layer (contours, paths, seams): DIR/layer_NNNNN.svg");
  cmd->add_flag("!--no-html", o->html, "Do not write report.html");
  return [o] { return run_plan(*o); };
}

}  // namespace polyaxis::app
