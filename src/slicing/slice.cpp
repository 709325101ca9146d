// Uniform planar slicing: triangles bucketed by the layers whose planes they span (a counting
// sort, exact against the same plane heights the tie rule uses), then layers cut in parallel.
#include "polyaxis/slicing/slice.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include "core/arena.h"
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>

#include <cmath>
#include <memory>

#include "adaptive.h"
#include "conformal.h"
#include "tilted.h"
#include "polyaxis/core/parallel_buckets.h"
#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::slicing {
namespace {

using core::ErrorCode;
using core::make_error;

bool finite_positive(double x) { return std::isfinite(x) && x > 0.0; }

// Plane height of uniform layer K: the single formula both the bucketing and the sections use.
double plane_height(double base, double t, std::int64_t k) { return base + (static_cast<double>(k) + 0.5) * t; }

}  // namespace

const char* layer_strategy_name(LayerStrategy s) {
  switch (s) {
    case LayerStrategy::kTilted: return "tilted";
    case LayerStrategy::kConformal: return "conformal";
    case LayerStrategy::kPlanar: break;
  }
  return "planar";
}

double overhang_estimate_mm2(const SliceResult& slices, double alpha_deg, double step_mm) {
  constexpr double kParallelCos = 1.0 - 1e-12;
  const double tan_a = std::tan(alpha_deg * 3.14159265358979323846 / 180.0);
  double total = 0.0;
  const std::vector<Layer>& ls = slices.layers;
  for (std::size_t k = 1; k < ls.size(); ++k) {
    const Layer &a = ls[k - 1], &b = ls[k];
    if (a.conformal && b.conformal) {  // footprints on the base (Layer::conformal), the torch along the gradient
      const auto grown = geom2d::offset(a.conformal->footprint, b.thickness_range().first * tan_a);
      total += geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of(b.conformal->footprint), geom2d::rings_of(grown)));
      continue;
    }
    const bool parallel = core::dot(a.frame.d, b.frame.d) >= kParallelCos;
    const std::vector<geom2d::Polygon> under = parallel ? a.polygons : project(a.polygons, a.frame, b.frame);
    const double t = parallel ? b.height_mm - a.height_mm : b.thickness_range().first;
    const auto grown = geom2d::offset(under, std::max(t * tan_a, step_mm));
    total += geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of(b.polygons), geom2d::rings_of(grown)));
  }
  return total;
}

core::Status validate(const SliceOptions& o) {
  if (!core::is_finite(o.direction) || core::norm(o.direction) < 1e-12) {
    return make_error(ErrorCode::kUsage, "--dir: the direction must be a finite non-zero vector");
  }
  // Tilted layers take the thickness range and the voldiff and overhang limits.
  if (o.tilted && (o.limits.cusp_mm || o.limits.area_deviation || o.snap_mm > 0.0 || !o.thickness_stock_mm.empty())) {
    return make_error(ErrorCode::kUsage,
                      "--tilted takes --layer (the step on the axis), --min, --max and --adaptive voldiff=,overhang=; cusp, "
                      "area, --snap and --thicknesses are for planar layers");
  }
  if (o.conformal_base && (o.conformal_base->empty() || !finite_positive(o.conformal_edge_mm))) {
    return make_error(ErrorCode::kUsage, "conformal layers: the base surface has no faces");
  }
  if (!o.adaptive && !o.tilted && !finite_positive(o.layer_mm)) return make_error(ErrorCode::kUsage, "--layer: must be a finite number > 0");
  if (o.adaptive || o.tilted || o.conformal_base) {
    if (!finite_positive(o.min_mm)) return make_error(ErrorCode::kUsage, "--min: must be a finite number > 0");
    if (!finite_positive(o.max_mm)) return make_error(ErrorCode::kUsage, "--max: must be a finite number > 0");
    if (o.min_mm > o.max_mm) {
      return make_error(ErrorCode::kUsage, fmt::format("--min {} is larger than --max {}", o.min_mm, o.max_mm));
    }
    const auto check = [](const std::optional<double>& v, const char* name) -> core::Status {
      if (v && !finite_positive(*v)) return make_error(ErrorCode::kUsage, fmt::format("--adaptive {}: must be a finite number > 0", name));
      return {};
    };
    if (auto s = check(o.limits.cusp_mm, "cusp"); !s) return s;
    if (auto s = check(o.limits.voldiff, "voldiff"); !s) return s;
    if (auto s = check(o.limits.area_deviation, "area"); !s) return s;
    if (auto s = check(o.limits.overhang_deg, "overhang"); !s) return s;
    if (o.limits.overhang_deg && *o.limits.overhang_deg >= 90.0) {
      return make_error(ErrorCode::kUsage, "--adaptive overhang: the angle must be below 90 degrees");
    }
    if (o.snap_mm < 0.0 || !std::isfinite(o.snap_mm)) return make_error(ErrorCode::kUsage, "--snap: must be a finite number >= 0");
    for (double t : o.thickness_stock_mm) {
      if (!finite_positive(t)) return make_error(ErrorCode::kUsage, "--thicknesses: every thickness must be a finite number > 0");
    }
  }
  return {};
}

namespace {
core::Result<SliceResult> slice_in_arena(const mesh::Mesh& mesh, const SliceOptions& options, const mesh::EdgeTopology* topology);
}  // namespace

core::Result<SliceResult> slice(const mesh::Mesh& mesh, const SliceOptions& options, const mesh::EdgeTopology* topology) {
  if (auto s = validate(options); !s) return s.error();
  if (mesh.triangles.empty()) return make_error(ErrorCode::kInvalidInput, "nothing to slice: the mesh has no faces");
  return core::with_threads(options.threads, [&] { return slice_in_arena(mesh, options, topology); });
}

namespace {
core::Result<SliceResult> slice_in_arena(const mesh::Mesh& mesh, const SliceOptions& options, const mesh::EdgeTopology* topology) {
  if (options.tilted) return detail::slice_tilted(mesh, options, topology);
  if (options.conformal_base) return detail::slice_conformal(mesh, options);
  const SectionContext ctx(mesh, options.direction, topology);
  if (options.adaptive) return detail::slice_adaptive(ctx, options);

  const double t = options.layer_mm;
  const double base = ctx.min_height();
  const double span = ctx.max_height() - base;
  const auto count = static_cast<std::int64_t>(std::ceil(span / t));
  constexpr std::int64_t kMaxLayers = 10'000'000;
  if (count > kMaxLayers) {
    return make_error(ErrorCode::kUsage, fmt::format("--layer {} mm gives {} layers over {} mm; at most {}", t, count, span, kMaxLayers));
  }
  const auto n = static_cast<std::size_t>(std::max<std::int64_t>(count, 1));
  // Layers each face spans: lo = first k with plane(k) > face_min, hi = last k with
  // plane(k) <= face_max; computed in both passes of the counting sort rather than stored.
  const std::size_t nf = mesh.triangles.size();
  const auto last = static_cast<std::int64_t>(n) - 1;
  auto layer_range = [&](std::uint32_t f) {
    const double fmin = ctx.face_min(f), fmax = ctx.face_max(f);
    std::int64_t a = static_cast<std::int64_t>(std::floor((fmin - base) / t - 0.5)) + 1;
    while (a > 0 && plane_height(base, t, a - 1) > fmin) --a;
    while (plane_height(base, t, a) <= fmin) ++a;
    std::int64_t b = static_cast<std::int64_t>(std::floor((fmax - base) / t - 0.5));
    while (plane_height(base, t, b + 1) <= fmax) ++b;
    while (b >= a && plane_height(base, t, b) > fmax) --b;
    return std::pair<std::int64_t, std::int64_t>{std::max<std::int64_t>(a, 0), std::min<std::int64_t>(b, last)};
  };
  // Faces bucketed into the layers they span, in face order within a layer whatever the thread
  // count (core::bucket_in_parts).
  std::vector<std::uint32_t> bucket;
  const std::vector<std::uint32_t> start = core::bucket_in_parts(nf, n, bucket, [&](std::size_t f, auto&& put) {
    const auto [lo, hi] = layer_range(static_cast<std::uint32_t>(f));
    for (std::int64_t k = lo; k <= hi; ++k) put(static_cast<std::size_t>(k), static_cast<std::uint32_t>(f));
  });
  SliceResult result;
  result.layers.resize(n);
  std::vector<std::uint32_t> open(n, 0);
  tbb::enumerable_thread_specific<SectionScratch> scratch;
  core::Progress progress("slicing", n);
  std::atomic<std::uint64_t> done{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8), [&](const tbb::blocked_range<std::size_t>& range) {
    SectionScratch& local = scratch.local();
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const double h = plane_height(base, t, static_cast<std::int64_t>(k));
      Layer& layer = result.layers[k];
      layer.index = static_cast<std::uint32_t>(k);
      layer.frame = plane_frame(ctx.direction(), h);
      layer.height_mm = h;
      layer.below_mm = layer.above_mm = t / 2.0;
      const std::span<const std::uint32_t> candidates(bucket.data() + start[k], start[k + 1] - start[k]);
      SectionResult s = section(ctx, h, layer.frame, candidates, local);
      layer.polygons = std::move(s.polygons);
      layer.area_mm2 = s.area_mm2;
      open[k] = s.open_chains;
    }
    done += range.size();
    if (tbb::this_task_arena::current_thread_index() == 0) progress.update(done);  // one thread draws
  });
  // Drop empty layers at the top (the last plane may clear a flat top).
  while (!result.layers.empty() && result.layers.back().polygons.empty()) result.layers.pop_back();
  for (std::size_t k = 0; k < result.layers.size(); ++k) {
    result.open_chains += open[k];
    result.total_area_mm2 += result.layers[k].area_mm2;
    result.volume_estimate_mm3 += result.layers[k].area_mm2 * result.layers[k].thickness_mm();
  }
  return result;
}

}  // namespace

}  // namespace polyaxis::slicing
