// polyaxis laminate PART --sheets 1,2,3,6 [--sheet-size 300x300] [--area-deviation 0.05] [--cusp MM]
// [--subslice MM] [--machine awj.json] [--process awj.json] [--set ...] -o DIR: sloped-edge thick
// layers from a stock of sheets, nested onto sheets, with one 5-axis waterjet program per sheet
// (lamination/lamination.h, waterjet.h; schema in docs/laminate.md).
#include <fmt/format.h>

#include <cstdio>
#include <sstream>

#include "commands.h"
#include "config_options.h"
#include "part_options.h"
#include "polyaxis/lamination/job.h"
#include "polyaxis/report/lamination_files.h"

namespace polyaxis::app {
namespace {

struct LaminateCommandOptions {
  lamination::LaminateRequest request;
  std::string sheets;
  std::string sheet_size = "300x300";
  std::string out_dir = "lamination";
  double cusp_mm = 0.0;
  bool json = false;
};

core::Status parse(LaminateCommandOptions& o) {
  std::stringstream s(o.sheets);
  std::string item;
  while (std::getline(s, item, ',')) {
    auto v = parse_number(item, "--sheets");
    if (!v) return v.error();
    o.request.options.sheets_mm.push_back(v.value());
  }
  const auto x = o.sheet_size.find('x');
  if (x == std::string::npos) return core::make_error(core::ErrorCode::kUsage, fmt::format("--sheet-size: expected WxH in mm, got '{}'", o.sheet_size));
  auto vw = parse_number(o.sheet_size.substr(0, x), "--sheet-size");
  if (!vw) return vw.error();
  auto vh = parse_number(o.sheet_size.substr(x + 1), "--sheet-size");
  if (!vh) return vh.error();
  o.request.sheet_w_mm = vw.value(), o.request.sheet_h_mm = vh.value();
  if (o.cusp_mm > 0.0) o.request.options.cusp_mm = o.cusp_mm;
  return {};
}

// The warnings' count on stderr, then lamination.json or one line on stdout.
void print_summary(const LaminateCommandOptions& o, const lamination::LaminateJob& job, const std::string& json) {
  if (!job.warnings.empty()) std::fprintf(stderr, "polyaxis: %zu warnings\n", job.warnings.size());
  if (o.json) {
    std::printf("%s", json.c_str());
    return;
  }
  const lamination::Lamination& l = job.lamination;
  double used = 0.0;
  for (const auto& s : job.sheets) used += s.utilisation;
  std::printf("%zu layers on %zu sheets (mean use %.1f %%), deviation %.1f mm3 sloped vs %.1f mm3 stepped -> %s/lamination.json\n", l.layers.size(),
              job.sheets.size(), job.sheets.empty() ? 0.0 : 100.0 * used / static_cast<double>(job.sheets.size()), l.sloped_deviation_mm3,
              l.stepped_deviation_mm3, o.out_dir.c_str());
}

int run_laminate(LaminateCommandOptions& o) {
  if (auto s = parse(o); !s) return report_error(s.error());
  o.request.on_warning = [](const std::string& w) { std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str()); };
  auto job = lamination::run_laminate_job(o.request);
  if (!job) return report_error(job.error());
  std::string json;
  if (auto s = report::write_lamination_files(o.out_dir, job.value(), &json); !s) return report_error(s.error());
  print_summary(o, job.value(), json);
  return 0;
}

}  // namespace

Runner add_laminate_command(CLI::App& app) {
  auto o = std::make_shared<LaminateCommandOptions>();
  o->request.part.repair.check_self_intersections = false;  // sections take the nonzero union; --strict checks
  CLI::App* cmd = app.add_subcommand("laminate", "Cut a part into sloped-edge sheet layers, nest them and write 5-axis waterjet programs");
  add_part_options(*cmd, o->request.part);
  cmd->add_option("--sheets", o->sheets, "Sheet thicknesses in stock, mm (e.g. 1,2,3,6)")->required();
  cmd->add_option("--sheet-size", o->sheet_size, "Sheet size WxH, mm")->capture_default_str();
  cmd->add_option("--area-deviation", o->request.options.area_deviation, "Largest area deviation of a layer's sloped edge from the part")
      ->capture_default_str()
      ->check(kFinitePositive & CLI::Range(1e-6, 10.0));
  cmd->add_option("--cusp", o->cusp_mm, "Largest gap between a cut and the part, mm (off when 0)")->check(kFinite & CLI::Range(0.0, 1000.0));
  cmd->add_option("--subslice", o->request.options.subslice_mm, "Thin sub-slice for convex multi-cuts, mm (0: the thinnest sheet)")
      ->capture_default_str()
      ->check(kFinite & CLI::Range(0.0, 1000.0));
  cmd->add_option("--machine", o->request.configs.machine_path, "Head-head machine file (JSON); default: examples/machines/awj5_head_ac.json");
  cmd->add_option("--process", o->request.configs.process_path, "Waterjet process file (JSON); default: examples/processes/awj_steel.json");
  cmd->add_option("--set", o->request.configs.sets, "Override a field: machine.limits.a.max=45 or process.kerf_mm=1 (repeatable)");
  cmd->add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print lamination.json to stdout");
  return [o] { return run_laminate(*o); };
}

}  // namespace polyaxis::app
