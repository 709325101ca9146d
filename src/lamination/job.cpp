#include "polyaxis/lamination/job.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace polyaxis::lamination {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void warn(const LaminateRequest& r, LaminateJob& job, std::string warning) {
  if (r.on_warning) r.on_warning(warning);
  job.warnings.push_back(std::move(warning));
}

core::Status load_configs(const LaminateRequest& r, LaminateJob& job) {
  const machine::ConfigSources& c = r.configs;
  auto m = machine::load_config_document(c.machine_path, default_waterjet_machine_json(), "waterjet machine");
  if (!m) return m.error();
  auto p = machine::load_config_document(c.process_path, default_waterjet_process_json(), "waterjet process");
  if (!p) return p.error();
  if (auto s = machine::apply_sets(m.value(), p.value(), c.sets); !s) return s.error();
  auto machine = machine::parse_machine(m.value().dump(), c.machine_path.empty() ? "the built-in waterjet machine" : c.machine_path);
  if (!machine) return machine.error();
  job.machine = std::move(machine.value());
  auto process = parse_waterjet_process(p.value().dump(), c.process_path.empty() ? "the built-in waterjet process" : c.process_path);
  if (!process) return process.error();
  job.process = std::move(process.value());
  if (!machine::tilts_head(job.machine.kind)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("machine '{}' ({}): a waterjet tilts its head over the sheet; give a head-head machine",
                                                                 job.machine.name, machine::kinematics_name(job.machine.kind)));
  }
  return {};
}

// What an engineer must know about the layers: limits the cuts could not keep.
void lamination_warnings(const LaminateRequest& r, const LaminateOptions& o, LaminateJob& job) {
  std::uint32_t at_limit = 0, holes_closed = 0;
  for (const auto& layer : job.lamination.layers) at_limit += layer.at_jet_limit, holes_closed += layer.holes_closed;
  if (!job.lamination.threshold_met) {
    warn(r, job, fmt::format("some layers exceed --area-deviation {:g} even on the thinnest sheet (see lamination.json)", o.area_deviation));
  }
  if (at_limit > 0) warn(r, job, fmt::format("{} edge samples are steeper than the jet's {:g}° and are cut at the limit", at_limit, o.max_jet_angle_deg));
  if (holes_closed > 0) {
    warn(r, job, fmt::format("{} holes narrow faster than the jet can follow and are left uncut (holes_closed in lamination.json)", holes_closed));
  }
}

}  // namespace

core::Result<LaminateJob> run_laminate_job(const LaminateRequest& r) {
  const auto start = Clock::now();
  if (!(std::isfinite(r.sheet_w_mm) && r.sheet_w_mm > 0.0 && std::isfinite(r.sheet_h_mm) && r.sheet_h_mm > 0.0)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("--sheet-size: {}x{} is not a finite positive size", r.sheet_w_mm, r.sheet_h_mm));
  }
  LaminateJob job;
  if (auto s = load_configs(r, job); !s) return s.error();
  LaminateOptions o = r.options;
  o.max_jet_angle_deg = std::min(std::fabs(job.machine.tilt_deg.min), std::fabs(job.machine.tilt_deg.max));
  auto loaded = r.mesh ? mesh::load_part(*r.mesh, r.part, r.part.path) : mesh::load_part(r.part);
  if (!loaded) return loaded.error();
  job.part = std::move(loaded.value());
  for (const auto& w : job.part.warnings) warn(r, job, w);

  auto stage = Clock::now();
  auto lam = laminate(job.part.repaired.mesh, o);
  if (!lam) return lam.error();
  job.lamination = std::move(lam.value());
  const double layers_s = since(stage);
  stage = Clock::now();
  auto sheets = nest_sheets(job.lamination, job.process, r.sheet_w_mm, r.sheet_h_mm, job.machine);
  if (!sheets) return sheets.error();
  job.sheets = std::move(sheets.value());
  const double nesting_s = since(stage);
  stage = Clock::now();

  job.meta = LaminateMeta{r.part.path, job.machine.name, job.process.name, o.sheets_mm, o.area_deviation, o.max_jet_angle_deg, job.process.kerf_mm, {}, 0.0, {}};
  for (const auto& sheet : job.sheets) {
    auto gcode = sheet_gcode(job.lamination, sheet, job.process, job.machine);
    if (!gcode) return gcode.error();
    job.programs.push_back(std::move(gcode.value()));
    job.meta.programs.push_back(fmt::format("sheet_{}.ngc", sheet.index));
  }
  job.meta.seconds = since(start);
  job.meta.stage_seconds = {{"read", job.part.read_s + job.part.repair_s}, {"layers", layers_s}, {"nesting", nesting_s}, {"programs", since(stage)}};
  lamination_warnings(r, o, job);
  return job;
}

}  // namespace polyaxis::lamination
