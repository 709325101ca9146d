// polyaxis laminate PART --sheets 1,2,3,6 [--sheet-size 300x300] [--area-deviation 0.05] [--cusp MM]
// [--subslice MM] [--machine awj.json] [--process awj.json] [--set ...] -o DIR: sloped-edge thick
// layers from a stock of sheets, nested onto sheets, with one 5-axis waterjet program per sheet
// (lamination/lamination.h, waterjet.h; schema in docs/laminate.md).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "commands.h"
#include "config_options.h"
#include "part_options.h"
#include "polyaxis/io/output_set.h"
#include "polyaxis/lamination/lamination.h"
#include "polyaxis/lamination/outputs.h"
#include "polyaxis/lamination/waterjet.h"

namespace polyaxis::app {
namespace {

struct LaminateCommandOptions {
  PartOptions part;
  std::string sheets;
  std::string sheet_size = "300x300";
  std::string machine_path, process_path;
  std::vector<std::string> sets;
  std::string out_dir = "lamination";
  lamination::LaminateOptions laminate;
  double cusp_mm = 0.0;
  bool json = false;
};

core::Status parse(LaminateCommandOptions& o, double& w, double& h) {
  std::stringstream s(o.sheets);
  std::string item;
  while (std::getline(s, item, ',')) {
    auto v = parse_number(item, "--sheets");
    if (!v) return v.error();
    o.laminate.sheets_mm.push_back(v.value());
  }
  const auto x = o.sheet_size.find('x');
  if (x == std::string::npos) return core::make_error(core::ErrorCode::kUsage, fmt::format("--sheet-size: expected WxH in mm, got '{}'", o.sheet_size));
  auto vw = parse_number(o.sheet_size.substr(0, x), "--sheet-size");
  if (!vw) return vw.error();
  auto vh = parse_number(o.sheet_size.substr(x + 1), "--sheet-size");
  if (!vh) return vh.error();
  w = vw.value(), h = vh.value();
  if (o.cusp_mm > 0.0) o.laminate.cusp_mm = o.cusp_mm;
  return {};
}

struct Configs {
  machine::MachineConfig machine;
  lamination::WaterjetProcess process;
};

core::Result<Configs> load(const LaminateCommandOptions& o) {
  auto m = load_config_document(o.machine_path, lamination::default_waterjet_machine_json(), "waterjet machine");
  if (!m) return m.error();
  auto p = load_config_document(o.process_path, lamination::default_waterjet_process_json(), "waterjet process");
  if (!p) return p.error();
  if (auto s = apply_sets(m.value(), p.value(), o.sets); !s) return s.error();
  Configs c;
  auto machine = machine::parse_machine(m.value().dump(), o.machine_path.empty() ? "the built-in waterjet machine" : o.machine_path);
  if (!machine) return machine.error();
  c.machine = std::move(machine.value());
  auto process = lamination::parse_waterjet_process(p.value().dump(), o.process_path.empty() ? "the built-in waterjet process" : o.process_path);
  if (!process) return process.error();
  c.process = std::move(process.value());
  if (!machine::tilts_head(c.machine.kind)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("machine '{}' ({}): a waterjet tilts its head over the sheet; give a head-head machine",
                                                                 c.machine.name, machine::kinematics_name(c.machine.kind)));
  }
  return c;
}

// Writes lamination.json, report.html and each sheet's SVG and program as one set (io::OutputSet),
// the programs last. JSON receives lamination.json's text.
core::Status write_set(const std::string& dir, const lamination::Lamination& l, const std::vector<lamination::Sheet>& sheets,
                       const lamination::WaterjetProcess& process, const lamination::LaminateMeta& meta,
                       const std::vector<std::string>& programs, std::string& json) {
  auto set = io::OutputSet::open(dir);
  if (!set) return set.error();
  json = lamination::lamination_json(l, sheets, meta);
  if (auto s = set.value().add("lamination.json", json); !s) return s;
  if (auto s = set.value().add("report.html", lamination::lamination_html(l, sheets, process, meta)); !s) return s;
  for (std::size_t i = 0; i < sheets.size(); ++i) {
    if (auto s = set.value().add(fmt::format("sheet_{}.svg", sheets[i].index), lamination::sheet_svg(l, sheets[i], process)); !s) return s;
  }
  for (std::size_t i = 0; i < programs.size(); ++i) {
    if (auto s = set.value().add(meta.programs[i], programs[i], io::Durability::kSynced); !s) return s;
  }
  return set.value().commit();
}

// The warnings (with their count) on stderr, then lamination.json or one line on stdout.
void print_summary(const LaminateCommandOptions& o, const lamination::Lamination& l, const std::vector<lamination::Sheet>& sheets,
                   std::size_t warnings, const std::string& json) {
  std::uint32_t at_limit = 0, holes_closed = 0;
  for (const auto& layer : l.layers) at_limit += layer.at_jet_limit, holes_closed += layer.holes_closed;
  if (!l.threshold_met) {
    std::fprintf(stderr, "polyaxis: warning: some layers exceed --area-deviation %g even on the thinnest sheet (see lamination.json)\n", o.laminate.area_deviation);
    ++warnings;
  }
  if (at_limit > 0) {
    std::fprintf(stderr, "polyaxis: warning: %u edge samples are steeper than the jet's %g° and are cut at the limit\n", at_limit, o.laminate.max_jet_angle_deg);
    ++warnings;
  }
  if (holes_closed > 0) {
    std::fprintf(stderr, "polyaxis: warning: %u holes narrow faster than the jet can follow and are left uncut (holes_closed in lamination.json)\n", holes_closed);
    ++warnings;
  }
  if (warnings > 0) std::fprintf(stderr, "polyaxis: %zu warnings\n", warnings);
  if (o.json) {
    std::printf("%s", json.c_str());
    return;
  }
  double used = 0.0;
  for (const auto& s : sheets) used += s.utilisation;
  std::printf("%zu layers on %zu sheets (mean use %.1f %%), deviation %.1f mm3 sloped vs %.1f mm3 stepped -> %s/lamination.json\n", l.layers.size(),
              sheets.size(), sheets.empty() ? 0.0 : 100.0 * used / static_cast<double>(sheets.size()), l.sloped_deviation_mm3, l.stepped_deviation_mm3,
              o.out_dir.c_str());
}

int run_laminate(LaminateCommandOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  auto since = [](std::chrono::steady_clock::time_point t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); };
  double sheet_w = 0, sheet_h = 0;
  if (auto s = parse(o, sheet_w, sheet_h); !s) return report_error(s.error());
  auto configs = load(o);
  if (!configs) return report_error(configs.error());
  const auto& machine = configs.value().machine;
  const auto& process = configs.value().process;
  o.laminate.max_jet_angle_deg = std::min(std::fabs(machine.tilt_deg.min), std::fabs(machine.tilt_deg.max));
  auto loaded = load_part(o.part);
  if (!loaded) return report_error(loaded.error());
  for (const auto& w : loaded.value().warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str());

  auto stage = std::chrono::steady_clock::now();
  auto lam = lamination::laminate(loaded.value().repaired.mesh, o.laminate);
  if (!lam) return report_error(lam.error());
  const lamination::Lamination& l = lam.value();
  const double layers_s = since(stage);
  stage = std::chrono::steady_clock::now();
  auto sheets = lamination::nest_sheets(l, process, sheet_w, sheet_h, machine);
  if (!sheets) return report_error(sheets.error());
  const double nesting_s = since(stage);
  stage = std::chrono::steady_clock::now();

  lamination::LaminateMeta meta{o.part.path, machine.name, process.name, o.laminate.sheets_mm, o.laminate.area_deviation,
                                o.laminate.max_jet_angle_deg, process.kerf_mm, {}, 0.0, {}};
  std::vector<std::string> programs;
  for (const auto& sheet : sheets.value()) {
    auto gcode = lamination::sheet_gcode(l, sheet, process, machine);
    if (!gcode) return report_error(gcode.error());
    programs.push_back(std::move(gcode.value()));
    meta.programs.push_back(fmt::format("sheet_{}.ngc", sheet.index));
  }
  meta.seconds = since(start);
  meta.stage_seconds = {{"read", loaded.value().read_s + loaded.value().repair_s}, {"layers", layers_s}, {"nesting", nesting_s}, {"programs", since(stage)}};
  std::string json;
  if (auto s = write_set(o.out_dir, l, sheets.value(), process, meta, programs, json); !s) return report_error(s.error());
  print_summary(o, l, sheets.value(), loaded.value().warnings.size(), json);
  return 0;
}

}  // namespace

Runner add_laminate_command(CLI::App& app) {
  auto o = std::make_shared<LaminateCommandOptions>();
  o->part.repair.check_self_intersections = false;  // sections take the nonzero union; --strict checks
  CLI::App* cmd = app.add_subcommand("laminate", "Cut a part into sloped-edge sheet layers, nest them and write 5-axis waterjet programs");
  add_part_options(*cmd, o->part);
  cmd->add_option("--sheets", o->sheets, "Sheet thicknesses in stock, mm (e.g. 1,2,3,6)")->required();
  cmd->add_option("--sheet-size", o->sheet_size, "Sheet size WxH, mm")->capture_default_str();
  cmd->add_option("--area-deviation", o->laminate.area_deviation, "Largest area deviation of a layer's sloped edge from the part")
      ->capture_default_str()
      ->check(kFinitePositive & CLI::Range(1e-6, 10.0));
  cmd->add_option("--cusp", o->cusp_mm, "Largest gap between a cut and the part, mm (off when 0)")->check(kFinite & CLI::Range(0.0, 1000.0));
  cmd->add_option("--subslice", o->laminate.subslice_mm, "Thin sub-slice for convex multi-cuts, mm (0: the thinnest sheet)")
      ->capture_default_str()
      ->check(kFinite & CLI::Range(0.0, 1000.0));
  cmd->add_option("--machine", o->machine_path, "Head-head machine file (JSON); default: examples/machines/awj5_head_ac.json");
  cmd->add_option("--process", o->process_path, "Waterjet process file (JSON); default: examples/processes/awj_steel.json");
  cmd->add_option("--set", o->sets, "Override a field: machine.limits.a.max=45 or process.kerf_mm=1 (repeatable)");
  cmd->add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print lamination.json to stdout");
  return [o] { return run_laminate(*o); };
}

}  // namespace polyaxis::app
