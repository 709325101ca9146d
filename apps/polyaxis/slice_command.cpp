// polyaxis slice PART [--dir X,Y,Z] [--layer MM | --adaptive LIMITS --min MM --max MM] [-o DIR]
// [--svg] [--json]: planar layers along any direction, written to DIR/layers.json.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.h"
#include "part_options.h"
#include "polyaxis/io/write_file.h"
#include "polyaxis/report/layers.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::app {
namespace {

struct SliceCommandOptions {
  PartOptions part;
  std::string dir = "0,0,1";
  std::string adaptive;
  std::string thicknesses;
  std::string out_dir = "slices";
  bool svg = false;
  bool json = false;
  bool tilted = false;
  slicing::SliceOptions slice;
};

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, sep)) parts.push_back(item);
  return parts;
}

core::Status parse(SliceCommandOptions& o) {
  const auto comps = split(o.dir, ',');
  if (comps.size() != 3) return core::make_error(core::ErrorCode::kUsage, fmt::format("--dir: expected X,Y,Z, got '{}'", o.dir));
  for (int i = 0; i < 3; ++i) {
    auto v = parse_number(comps[static_cast<std::size_t>(i)], "--dir");
    if (!v) return v.error();
    o.slice.direction[i] = v.value();
  }
  if (!o.adaptive.empty()) {
    o.slice.adaptive = true;
    for (const auto& item : split(o.adaptive, ',')) {
      const auto eq = item.find('=');
      const std::string key = item.substr(0, eq);
      if (eq == std::string::npos) {
        return core::make_error(core::ErrorCode::kUsage, fmt::format("--adaptive: expected KEY=VALUE, got '{}'", item));
      }
      auto v = parse_number(item.substr(eq + 1), "--adaptive " + key);
      if (!v) return v.error();
      if (key == "cusp") o.slice.limits.cusp_mm = v.value();
      else if (key == "voldiff") o.slice.limits.voldiff = v.value();
      else if (key == "area") o.slice.limits.area_deviation = v.value();
      else if (key == "overhang") o.slice.limits.overhang_deg = v.value();
      else {
        return core::make_error(core::ErrorCode::kUsage,
                                fmt::format("--adaptive: unknown limit '{}' (known: cusp, voldiff, area, overhang)", key));
      }
    }
  }
  if (!o.thicknesses.empty()) {
    for (const auto& item : split(o.thicknesses, ',')) {
      auto v = parse_number(item, "--thicknesses");
      if (!v) return v.error();
      o.slice.thickness_stock_mm.push_back(v.value());
    }
  }
  if (o.tilted) {
    // Tilted layers take --adaptive's voldiff and overhang limits without being adaptive planar ones.
    o.slice.tilted = true;
    o.slice.adaptive = false;
  }
  return slicing::validate(o.slice);
}

int run_slice(SliceCommandOptions& o) {
  if (auto s = parse(o); !s) return report_error(s.error());
  auto loaded = load_part(o.part);
  if (!loaded) return report_error(loaded.error());
  const LoadedPart& part = loaded.value();
  for (const auto& w : part.warnings) std::fprintf(stderr, "polyaxis: warning: %s\n", w.c_str());
  auto sliced = slicing::slice(part.repaired.mesh, o.slice, &part.repaired.topology);
  if (!sliced) return report_error(sliced.error());
  const slicing::SliceResult& r = sliced.value();
  std::size_t warnings = part.warnings.size();
  if (r.open_chains > 0) {
    std::fprintf(stderr, "polyaxis: warning: %u section chains did not close (the mesh is open) and were dropped\n", r.open_chains);
    ++warnings;
  }
  if (r.limit_violations > 0) {
    std::fprintf(stderr, "polyaxis: warning: %u layers could not meet every adaptive limit even at --min\n", r.limit_violations);
    ++warnings;
  }
  if (warnings > 0) std::fprintf(stderr, "polyaxis: %zu warnings\n", warnings);

  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) return report_error(core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot create: {}", o.out_dir, ec.message())));
  const report::LayersMeta meta{o.part.path, o.slice};
  auto layers_file = io::AtomicFile::create(o.out_dir + "/layers.json");
  if (!layers_file) return report_error(layers_file.error());
  if (auto s = report::write_layers_json(layers_file.value(), r, meta); !s) return report_error(s.error());
  if (auto s = layers_file.value().commit(io::Durability::kAtomic); !s) return report_error(s.error());
  if (o.svg) {
    for (const auto& layer : r.layers) {
      const std::string path = fmt::format("{}/layer_{:05d}.svg", o.out_dir, layer.index);
      if (auto s = io::write_file_atomic(path, report::layer_svg(layer), io::Durability::kAtomic); !s) return report_error(s.error());
    }
  }
  if (o.json) {
    std::printf("%s\n", report::slice_summary_json(r, meta).c_str());
  } else {
    double tmin = r.layers.empty() ? 0.0 : 1e300, tmax = 0.0;
    for (const auto& l : r.layers) tmin = std::min(tmin, l.thickness_range().first), tmax = std::max(tmax, l.thickness_range().second);
    std::printf("%zu %slayers (%.4g-%.4g mm) %s (%.4g, %.4g, %.4g), area %.1f mm2, volume estimate %.1f mm3 -> %s/layers.json\n",
                r.layers.size(), o.tilted ? "tilted " : "", tmin, tmax, o.tilted ? "from" : "along", o.slice.direction.x, o.slice.direction.y, o.slice.direction.z, r.total_area_mm2,
                r.volume_estimate_mm3, o.out_dir.c_str());
  }
  return 0;
}

}  // namespace

Runner add_slice_command(CLI::App& app) {
  auto o = std::make_shared<SliceCommandOptions>();
  o->part.repair.check_self_intersections = false;  // slicing takes the nonzero union anyway
  CLI::App* cmd = app.add_subcommand("slice", "Cut a part into planar layers along any direction");
  add_part_options(*cmd, o->part);
  cmd->add_option("--dir", o->dir, "Build direction X,Y,Z (any length)")->capture_default_str();
  // Thicknesses: a micrometre to a metre (1e308 made no layer and exited 0).
  const CLI::Validator thickness = kFinitePositive & CLI::Range(1e-3, 1000.0);
  cmd->add_option("--layer", o->slice.layer_mm, "Uniform layer thickness, mm")->capture_default_str()->check(thickness);
  cmd->add_option("--adaptive", o->adaptive,
                  "Adaptive thickness under limits, e.g. cusp=0.05,voldiff=0.1,area=0.2,overhang=30 (mm, ratio, ratio, degrees)");
  cmd->add_option("--min", o->slice.min_mm, "Adaptive: thinnest layer, mm")->capture_default_str()->check(thickness);
  cmd->add_option("--max", o->slice.max_mm, "Adaptive: thickest layer, mm")->capture_default_str()->check(thickness);
  cmd->add_option("--snap", o->slice.snap_mm, "Adaptive: thicknesses are multiples of this, mm (machine Z resolution)")
      ->check(kFinite & CLI::Range(0.0, 1000.0));
  cmd->add_option("--thicknesses", o->thicknesses, "Adaptive: thicknesses to choose from, mm, e.g. 0.5,1,2 (a sheet stock)");
  cmd->add_option("-o,--out", o->out_dir, "Output directory for layers.json and SVGs")->capture_default_str();
  cmd->add_flag("--svg", o->svg, "Also write one SVG per layer");
  cmd->add_flag("--tilted", o->tilted,
                "Tilted \"3-D\" layers along the centroidal axis (Ruan): --layer is the step on the axis, every thickness stays in "
                "[--min, --max]; limits from --adaptive voldiff=,overhang=");
  cmd->add_flag("--json", o->json, "Print a JSON summary instead of one line");
  cmd->add_option("--threads", o->slice.threads, "Worker threads (0: all cores); output is identical for any count");

  return [o] { return run_slice(*o); };
}

}  // namespace polyaxis::app
