// polyaxis view PLAN.json [-o FILE] [--gcode G [--machine M] [--process P] [--set K=V]]: writes the
// 3-D report page of a plan written by `polyaxis plan` (default: report.html beside PLAN.json); with
// the plan's G-code and its machine, the page plays the program back on the machine.
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "config_options.h"
#include "polyaxis/io/text_file.h"
#include "polyaxis/io/write_file.h"
#include "polyaxis/report/plan_view.h"
#include "polyaxis/report/report_html.h"
#include "polyaxis/verify/playback.h"

namespace polyaxis::app {
namespace {

constexpr std::uint64_t kMaxPlanBytes = 4ull << 30;

struct ViewOptions {
  std::string plan_path;
  std::string out_path;
  std::size_t max_points = report::kViewerMaxPoints;
  std::string gcode_path;  // the plan's program: machine playback when given
  ConfigOptions configs;   // the machine (and process codes) it runs on
};

int run_view(const ViewOptions& o) {
  auto text = io::read_text_file(o.plan_path, kMaxPlanBytes);
  if (!text) return report_error(text.error());
  auto view = report::read_plan_view(text.value(), o.plan_path);
  if (!view) return report_error(view.error());
  const std::string out =
      o.out_path.empty() ? (std::filesystem::path(o.plan_path).parent_path() / "report.html").string() : o.out_path;
  if (!o.gcode_path.empty()) {
    // The program as its machine's controller reads it (an error names the line of G-code that
    // does not belong to this machine, exit 3).
    auto configs = load_configs(o.configs);
    if (!configs) return report_error(configs.error());
    auto gcode = io::read_text_file(o.gcode_path, kMaxPlanBytes);
    if (!gcode) return report_error(gcode.error());
    auto frames = verify::playback_frames(configs.value().machine, configs.value().process, gcode.value());
    if (!frames) return report_error(core::make_error(frames.error().code, fmt::format("{}: {}", o.gcode_path, frames.error().message)));
    view.value().playback = report::ViewPlayback{configs.value().machine, std::move(frames.value())};
  }
  report::HtmlOptions options;
  options.max_points = o.max_points;
  if (auto s = io::write_file_atomic(out, report::report_html(view.value(), report::viewer_bundle(), options), io::Durability::kAtomic);
      !s) {
    return report_error(s.error());
  }
  std::printf("%zu layers, %zu program points -> %s\n", view.value().layers.size(), view.value().program.size(), out.c_str());
  return 0;
}

}  // namespace

Runner add_view_command(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view", "Write the 3-D report page (report.html) of a plan.json");
  cmd->add_option("plan", o->plan_path, "plan.json written by polyaxis plan")->required();
  cmd->add_option("-o,--out", o->out_path, "Output HTML file (default: report.html beside the plan)");
  cmd->add_option("--max-points", o->max_points, "Show at most about this many program points (decimated beyond)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1000}, std::size_t{100'000'000}));
  cmd->add_option("--gcode", o->gcode_path, "The plan's G-code: the page plays it back on the machine (--machine, --process)");
  add_config_options(*cmd, o->configs, true);
  return [o] { return run_view(*o); };
}

}  // namespace polyaxis::app
