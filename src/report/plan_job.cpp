#include "polyaxis/report/plan_job.h"

#include <fmt/format.h>

#include <cmath>
#include <sstream>

#include "polyaxis/analysis/root_base.h"

namespace polyaxis::report {
namespace {

core::Error usage(std::string message) { return core::Error{core::ErrorCode::kUsage, std::move(message)}; }

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
      return usage(fmt::format("--dir: '{}' is not a finite number", item));
    }
  }
  if (i != 3) return usage(fmt::format("--dir: expected X,Y,Z, got '{}'", text));
  return {};
}

// The request's names as plan_part's options, every contradiction refused.
core::Status resolve_options(const PlanRequest& r, planner::PlanPartOptions& opt) {
  if (auto s = parse_direction(r.dir, opt.direction); !s) return s;
  opt.plan.tilt_on_overhang = !r.no_tilt;
  std::string strategy = r.strategy;
  if (strategy != "single" && strategy != "decompose" && strategy != "auto") {
    return usage(fmt::format("--strategy: '{}' is not single, decompose or auto", strategy));
  }
  if (r.decompose) {
    if (strategy != "auto" && strategy != "decompose") return usage("--decompose is --strategy decompose; it contradicts --strategy " + strategy);
    strategy = "decompose";
  }
  if (r.layers == "planar") {
    opt.plan.layers = planner::LayerChoice::kPlanar;
  } else if (r.layers == "tilted") {
    opt.plan.layers = planner::LayerChoice::kTilted;
  } else if (r.layers == "conformal") {
    opt.plan.layers = planner::LayerChoice::kConformal;
  } else if (r.layers == "auto") {
    opt.plan.layers = planner::LayerChoice::kAuto;
  } else {
    return usage(fmt::format("--layers: '{}' is not planar, tilted, conformal or auto", r.layers));
  }
  if (r.no_tilt && (opt.plan.layers == planner::LayerChoice::kTilted || opt.plan.layers == planner::LayerChoice::kConformal)) {
    return usage(fmt::format("--layers {} turns the torch with each layer; it contradicts --no-tilt", r.layers));
  }
  opt.strategy = strategy == "single" ? planner::Strategy::kSingle
                 : strategy == "decompose" ? planner::Strategy::kDecompose : planner::Strategy::kAuto;
  if (!r.root_base.empty() && opt.strategy == planner::Strategy::kSingle) {
    return usage("--root-base places the root region: it needs --strategy decompose or auto");
  }
  auto root_base = analysis::parse_root_base(r.root_base);
  if (!root_base) return root_base.error();
  opt.root_base = root_base.value();
  if (opt.plan.layers == planner::LayerChoice::kConformal && r.substrate.empty() && opt.prebuilt.empty()) {
    return usage("--layers conformal: the layers follow a prebuilt part's surface; give one with --substrate or --prebuilt");
  }
  if (!r.substrate.empty() && !opt.prebuilt.empty()) return usage("--substrate gives the prebuilt part as its own mesh; it contradicts --prebuilt");
  if (!opt.prebuilt.empty() && opt.strategy == planner::Strategy::kSingle) {
    return usage("--prebuilt names regions of the decomposition; it contradicts --strategy single");
  }
  return {};
}

void warn(const PlanRequest& r, PlanJob& job, const std::string& warning) {
  job.warnings.push_back(warning);
  if (r.on_warning) r.on_warning(warning);
}

// The part, and the substrate read as the part is (in its units, --scale) into OPT.
core::Status load_parts(const PlanRequest& r, PlanJob& job, planner::PlanPartOptions& opt) {
  auto loaded = r.mesh ? mesh::load_part(*r.mesh, r.part, r.part.path) : mesh::load_part(r.part);
  if (!loaded) return loaded.error();
  job.part = std::move(loaded.value());
  for (const auto& w : job.part.warnings) warn(r, job, w);
  if (r.substrate.empty()) return {};
  mesh::LoadOptions substrate = r.part;
  substrate.path = r.substrate;
  auto base = mesh::load_part(substrate);
  if (!base) {
    core::Error e = base.error();
    e.message = "--substrate: " + e.message;
    return e;
  }
  for (const auto& w : base.value().warnings) warn(r, job, "--substrate: " + w);
  opt.substrate = std::move(base.value().repaired.mesh);
  return {};
}

}  // namespace

core::Result<std::unique_ptr<PlanJob>> run_plan_job(const PlanRequest& request) {
  planner::PlanPartOptions opt = request.options;
  if (auto s = resolve_options(request, opt); !s) return s.error();
  auto job = std::make_unique<PlanJob>();
  auto configs = machine::load_configs(request.configs);
  if (!configs) return configs.error();
  job->configs = std::move(configs.value());
  if (auto s = load_parts(request, *job, opt); !s) return s.error();
  auto result = planner::plan_part(job->part.repaired, job->configs.machine, job->configs.process, opt);
  if (!result) return result.error();
  job->result = std::move(result.value());
  for (const std::string& w : job->result.warnings) warn(request, *job, w);
  job->meta = plan_meta(job->result, job->configs.machine, job->configs.process, request.part.path, job->part.read_s, job->part.repair_s);
  auto set = make_plan_set(job->result, job->configs.machine, job->meta);
  if (!set) return set.error();
  job->set = std::move(set.value());
  return job;
}

}  // namespace polyaxis::report
