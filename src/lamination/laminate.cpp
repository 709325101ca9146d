// Layer choice and the deviation volumes (lamination.h).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/arena.h"
#include <tbb/parallel_for.h>

#include "edges.h"
#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/lamination/lamination.h"
#include "polyaxis/mesh/properties.h"

namespace polyaxis::lamination {
namespace {

using detail::SectionStack;

constexpr double kHeightTolMm = 1e-6;     // a remainder this thin is no layer
constexpr std::uint32_t kMinDeviationSamples = 4;
constexpr std::uint32_t kDeviationSamplesPerSubslice = 4;
constexpr std::uint32_t kMaxDeviationSamples = 64;

// Heights at which a layer's deviation is measured: the middles of equal parts of its thickness.
std::vector<double> deviation_heights(const Layer& layer) {
  const std::uint32_t n = std::clamp(layer.subslices * kDeviationSamplesPerSubslice, kMinDeviationSamples, kMaxDeviationSamples);
  std::vector<double> h;
  for (std::uint32_t j = 0; j < n; ++j) h.push_back(layer.z_bottom_mm + (j + 0.5) * layer.thickness_mm / n);
  return h;
}

std::vector<geom2d::Polygon> kept_layer_section(const Layer& layer, double h) {
  std::vector<geom2d::Ring> rings;
  for (const auto& piece : layer.pieces) {
    for (auto& p : kept_section(layer, piece, h)) {
      auto r = geom2d::rings_of({p});
      rings.insert(rings.end(), r.begin(), r.end());
    }
  }
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

struct Deviation {
  double worst_ratio = 0.0;  // max over heights of A(S Δ E) / A(S)
  double sloped_mm3 = 0.0, stepped_mm3 = 0.0;
};

// The layer's deviation against the part: the area ratio that chooses it and both volumes.
Deviation measure(const SectionStack& stack, const Layer& layer) {
  Deviation d;
  const auto mid = stack.at(layer.z_ref_mm);
  const auto mid_rings = geom2d::rings_of(mid);
  const double mid_area = geom2d::area_mm2(mid);
  const auto heights = deviation_heights(layer);
  const double dz = layer.thickness_mm / static_cast<double>(heights.size());
  for (double h : heights) {
    const auto part = stack.at(h);
    const auto part_rings = geom2d::rings_of(part);
    const double sloped = geom2d::area_mm2(geom2d::xor_rings(part_rings, geom2d::rings_of(kept_layer_section(layer, h))));
    const double stepped = geom2d::area_mm2(geom2d::xor_rings(part_rings, mid_rings));
    // Above the part's top the layer's excess is the sheet's thickness, not its edge: it counts in
    // the volumes, not in the ratio that chooses the sheet (the top takes the thinnest that covers).
    if (h < stack.max_z()) d.worst_ratio = std::max(d.worst_ratio, sloped / std::max({geom2d::area_mm2(part), mid_area, 1e-12}));
    d.sloped_mm3 += sloped * dz;
    d.stepped_mm3 += stepped * dz;
  }
  return d;
}

// The layer cut with vertical edges that keep all its material (each layer at the union of the
// part's sections over its height), against the part: the stair step that, like the sloped edge,
// never gouges.
double covering_mm3(const SectionStack& stack, const Layer& layer) {
  const auto heights = deviation_heights(layer);
  const double dz = layer.thickness_mm / static_cast<double>(heights.size());
  std::vector<std::vector<geom2d::Ring>> parts;
  std::vector<geom2d::Ring> all;
  for (double h : heights) {
    parts.push_back(geom2d::rings_of(stack.at(h)));
    all.insert(all.end(), parts.back().begin(), parts.back().end());
  }
  const auto cover = geom2d::rings_of(geom2d::union_rings(all, geom2d::FillRule::kNonZero));
  double v = 0.0;
  for (const auto& part : parts) v += geom2d::area_mm2(geom2d::xor_rings(part, cover)) * dz;
  return v;
}

core::Status validate(const LaminateOptions& o) {
  if (o.sheets_mm.empty()) return core::make_error(core::ErrorCode::kUsage, "--sheets: give at least one sheet thickness");
  for (double t : o.sheets_mm) {
    if (!std::isfinite(t) || t < 1e-3 || t > 1000.0) {
      return core::make_error(core::ErrorCode::kUsage, fmt::format("--sheets: thickness {} mm is outside [0.001, 1000]", t));
    }
  }
  if (!(o.area_deviation > 0.0) || !std::isfinite(o.area_deviation)) {
    return core::make_error(core::ErrorCode::kUsage, "--area-deviation must be a finite number above 0");
  }
  if (o.cusp_mm && !(*o.cusp_mm > 0.0 && std::isfinite(*o.cusp_mm))) return core::make_error(core::ErrorCode::kUsage, "--cusp must be above 0");
  if (!(o.sample_mm >= 0.01 && o.sample_mm <= 1000.0)) return core::make_error(core::ErrorCode::kUsage, "sample spacing must be in [0.01, 1000] mm");
  if (!(o.subslice_mm >= 0.0 && o.subslice_mm <= 1000.0)) return core::make_error(core::ErrorCode::kUsage, "--subslice must be in [0, 1000] mm");
  if (!(o.max_jet_angle_deg >= 0.0 && o.max_jet_angle_deg < 89.0)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("the jet's angle limit {}° must be in [0, 89)", o.max_jet_angle_deg));
  }
  return {};
}

struct Candidate {
  Layer layer;
  Deviation deviation;
  bool meets = false;
};



core::Result<Lamination> laminate_in_arena(const mesh::Mesh& mesh, const LaminateOptions& options_in) {
  LaminateOptions o = options_in;
  std::sort(o.sheets_mm.begin(), o.sheets_mm.end(), std::greater<>());
  o.sheets_mm.erase(std::unique(o.sheets_mm.begin(), o.sheets_mm.end()), o.sheets_mm.end());
  const double thinnest = o.sheets_mm.back();
  if (o.subslice_mm <= 0.0) o.subslice_mm = thinnest;

  const SectionStack stack(mesh);
  const mesh::SurfaceDistance surface(mesh);
  if (surface.empty() || !(stack.max_z() > stack.min_z())) return core::make_error(core::ErrorCode::kInfeasible, "the part has no height to laminate");
  const detail::EdgeContext context{stack, surface, o};

  Lamination result;
  result.part_volume_mm3 = mesh::signed_volume(mesh);
  core::Progress progress("laminating (µm of height)", static_cast<std::uint64_t>(std::ceil((stack.max_z() - stack.min_z()) * 1000.0)));
  double z = stack.min_z();
  while (stack.max_z() - z > kHeightTolMm) {
    const double remainder = stack.max_z() - z;
    std::vector<double> ts;
    for (double t : o.sheets_mm) {
      if (t <= remainder + kHeightTolMm) ts.push_back(t);
    }
    if (ts.empty()) ts.push_back(thinnest);  // the top: the thinnest sheet, standing out
    std::vector<Candidate> candidates(ts.size());
    tbb::parallel_for(std::size_t{0}, ts.size(), [&](std::size_t i) {
      Candidate& c = candidates[i];
      c.layer = detail::build_layer(context, z, ts[i]);
      c.deviation = measure(stack, c.layer);
      c.meets = c.deviation.worst_ratio <= o.area_deviation && (!o.cusp_mm || c.layer.max_gap_mm <= *o.cusp_mm);
    });
    auto chosen = std::find_if(candidates.begin(), candidates.end(), [](const Candidate& c) { return c.meets; });
    if (chosen == candidates.end()) {
      chosen = candidates.end() - 1;  // the thinnest that fits
      result.threshold_met = false;
    }
    Layer layer = std::move(chosen->layer);
    layer.index = static_cast<std::uint32_t>(result.layers.size());
    layer.area_deviation = chosen->deviation.worst_ratio;
    result.sloped_deviation_mm3 += chosen->deviation.sloped_mm3;
    result.stepped_deviation_mm3 += chosen->deviation.stepped_mm3;
    result.covering_deviation_mm3 += covering_mm3(stack, chosen->layer);
    z += layer.thickness_mm;
    result.layers.push_back(std::move(layer));
    progress.update(static_cast<std::uint64_t>(std::min(z - stack.min_z(), stack.max_z() - stack.min_z()) * 1000.0));
  }
  return result;
}

}  // namespace

core::Result<Lamination> laminate(const mesh::Mesh& mesh, const LaminateOptions& options) {
  if (auto s = validate(options); !s) return s.error();
  core::ProgressScope scope(options.progress);
  return core::with_threads(options.threads, [&] { return laminate_in_arena(mesh, options); });
}

}  // namespace polyaxis::lamination
