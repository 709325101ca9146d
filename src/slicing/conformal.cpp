#include "polyaxis/slicing/conformal.h"

#include "conformal.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::slicing {

namespace {

constexpr double kLiftToleranceMm = 1e-6;
constexpr int kLiftIterations = 80;
// A layer's span is sampled at its contour vertices and at interior points of a grid with at most
// this many cells over the section's box.
constexpr double kSpanGridCells = 400.0;
constexpr double kSpanGridMinMm = 0.5;  // and cells no smaller than this

struct PointBitsHash {
  std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::uint64_t v : k) h = (h ^ v) * 0xff51afd7ed558ccdull, h ^= h >> 33;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace

std::optional<Lifted> lift(const mesh::SurfaceDistance& base, Vec3 d, double level, Vec3 p, double s, std::optional<mesh::Nearest>* near) {
  double lo = -INFINITY, hi = INFINITY;  // s below the level, s above it
  std::optional<mesh::Nearest> own;       // the step before's answer: the search starts from it
  std::optional<mesh::Nearest>& before = near != nullptr ? *near : own;
  for (int it = 0; it < kLiftIterations; ++it) {
    const Vec3 at = p + d * s;
    const mesh::Nearest n = before ? base.nearest(at, *before) : base.nearest(at);
    before = n;
    const double away = core::norm(at - n.point);
    const Vec3 g = away > 1e-9 ? (at - n.point) / (n.signed_mm < 0.0 ? -away : away) : n.normal;
    const double r = n.signed_mm - level, rise = core::dot(g, d);
    if (std::fabs(r) <= kLiftToleranceMm) {
      if (rise < kMinRise) return std::nullopt;
      return Lifted{at, core::normalized(g)};
    }
    (r < 0.0 ? lo : hi) = s;
    double next = s - r / std::clamp(rise, kMinRise, 1.0);
    if (std::isfinite(lo) && std::isfinite(hi) && !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    s = next;
  }
  return std::nullopt;
}

std::optional<Lifted> lift(const mesh::SurfaceDistance& base, const Layer& layer, Vec3 p, std::optional<mesh::Nearest>* near) {
  if (!layer.conformal) return std::nullopt;
  const Vec3 d = layer.frame.d;
  return lift(base, d, layer.conformal->level_mm, p, layer.height_mm - core::dot(p, d), near);
}

std::optional<mesh::Mesh> refined_for_levels(const mesh::Mesh& mesh, const mesh::SurfaceDistance& base, double min_edge_mm) {
  const double min2 = min_edge_mm * min_edge_mm;
  // The distance at each point asked, by its bits: refine asks each edge from both its faces and
  // again each time a face returns to its queue, and a split edge's midpoint becomes a vertex.
  std::unordered_map<std::array<std::uint64_t, 3>, double, PointBitsHash> known;
  auto distance = [&](Vec3 p) {
    const std::array<std::uint64_t, 3> key{std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y), std::bit_cast<std::uint64_t>(p.z)};
    auto [it, fresh] = known.try_emplace(key, 0.0);
    if (fresh) it->second = base.nearest(p).signed_mm;
    return it->second;
  };
  auto curved = [&](Vec3 a, Vec3 b) {
    if (core::dot(b - a, b - a) <= min2) return false;
    return std::fabs(distance((a + b) * 0.5) - 0.5 * (distance(a) + distance(b))) > kFieldToleranceMm;
  };
  return mesh::refine(mesh, curved, kMaxRefinedFaces);
}

namespace detail {

namespace {

// Even-odd point-in-rings test, (u, v) in units.
bool inside(const std::vector<geom2d::Ring>& rings, double u, double v) {
  bool in = false;
  for (const geom2d::Ring& r : rings) {
    for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
      const double ui = static_cast<double>(r[i].x), vi = static_cast<double>(r[i].y);
      const double uj = static_cast<double>(r[j].x), vj = static_cast<double>(r[j].y);
      if ((vi > v) != (vj > v) && u < (uj - ui) * (v - vi) / (vj - vi) + ui) in = !in;
    }
  }
  return in;
}

// Lifts LAYER's contour rings and interior grid points onto its surface (PLANE: the frame the
// polygons are in, GUESS: a height along d to search from); sets the layer's frame, height and
// span. Returns a message naming the point where the surface folds over, empty on success.
std::string lift_layer(const mesh::SurfaceDistance& base, const Frame& plane, double guess, Layer& layer) {
  ConformalLayer& c = *layer.conformal;
  const Vec3 d = plane.d;
  double low = INFINITY, high = -INFINITY;
  double s = guess;
  Vec3 axis;
  auto take = [&](Vec3 p) -> bool {
    const auto l = lift(base, d, c.level_mm, p, s);
    if (!l) return false;
    s = core::dot(l->point, d), axis = l->axis;
    low = std::min(low, s), high = std::max(high, s);
    return true;
  };
  auto fold = [&](Vec3 p) {
    return fmt::format("conformal layer {} ({:.3f} mm from the base) is no height field along the region's direction near ({:.2f}, {:.2f}, "
                       "{:.2f}): the distance's gradient turns more than {:.0f} deg from it",
                       layer.index, c.level_mm, p.x, p.y, p.z, std::acos(kMinRise) * 180.0 / 3.14159265358979323846);
  };
  const std::vector<geom2d::Ring> rings = geom2d::rings_of(layer.polygons);
  std::int64_t u0 = INT64_MAX, u1 = INT64_MIN, v0 = INT64_MAX, v1 = INT64_MIN;
  std::vector<geom2d::Ring> feet;
  for (const geom2d::Ring& ring : rings) {
    std::vector<Vec3> lifted, gradients;
    lifted.reserve(ring.size());
    gradients.reserve(ring.size());
    geom2d::Ring foot;
    for (const geom2d::Point& q : ring) {
      u0 = std::min(u0, q.x), u1 = std::max(u1, q.x), v0 = std::min(v0, q.y), v1 = std::max(v1, q.y);
      const Vec3 p = plane.to_world(geom2d::to_mm(q.x), geom2d::to_mm(q.y));
      if (!take(p)) return fold(p);
      lifted.push_back(p + d * (s - core::dot(p, d)));
      gradients.push_back(axis);
      const Vec3 f = lifted.back() - axis * c.level_mm - plane.origin;
      foot.push_back({geom2d::to_units(core::dot(f, plane.u)), geom2d::to_units(core::dot(f, plane.v))});
    }
    c.contours.push_back(std::move(lifted));
    c.axes.push_back(std::move(gradients));
    feet.push_back(std::move(foot));
  }
  c.footprint = geom2d::union_rings(feet, geom2d::FillRule::kNonZero);
  double stretch = 0.0;
  int inside_samples = 0;
  if (!rings.empty()) {
    const double w = static_cast<double>(u1 - u0), h = static_cast<double>(v1 - v0);
    const double step = std::max(std::sqrt(w * h / kSpanGridCells), static_cast<double>(geom2d::to_units(kSpanGridMinMm)));
    for (double u = static_cast<double>(u0) + step / 2; u < static_cast<double>(u1); u += step) {
      for (double v = static_cast<double>(v0) + step / 2; v < static_cast<double>(v1); v += step) {
        if (!inside(rings, u, v)) continue;
        const Vec3 p = plane.to_world(geom2d::to_mm(static_cast<std::int64_t>(u)), geom2d::to_mm(static_cast<std::int64_t>(v)));
        if (!take(p)) return fold(p);
        stretch += 1.0 / core::dot(axis, d), ++inside_samples;  // the surface over a patch of the plane: its area / rise
      }
    }
  }
  // The layer's area on its surface: the projected area times the mean stretch over the grid.
  if (inside_samples > 0) layer.area_mm2 *= stretch / inside_samples;
  if (!std::isfinite(low)) low = high = guess;
  c.low_mm = low, c.high_mm = high;
  layer.height_mm = 0.5 * (low + high);
  layer.frame = plane_frame(d, layer.height_mm);
  return {};
}

}  // namespace

core::Result<SliceResult> slice_conformal(const mesh::Mesh& region, const SliceOptions& o) {
  const mesh::SurfaceDistance& base = *o.conformal_base;
  const Vec3 d = core::normalized(o.direction);
  const std::optional<mesh::Mesh> refined = refined_for_levels(region, base, o.conformal_edge_mm);
  if (!refined) {
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("conformal layers: the region would need more than {} faces to follow the levels", kMaxRefinedFaces));
  }
  const mesh::Mesh& fine = *refined;
  std::vector<double> field(fine.vertices.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, field.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) field[i] = base.nearest(fine.vertices[i]).signed_mm;
  });
  const auto [lo_it, hi_it] = std::minmax_element(field.begin(), field.end());
  const double start = std::max(0.0, *lo_it), farthest = *hi_it;
  if (*lo_it > o.max_mm) {
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("conformal layers: the region does not rest on the base surface (its nearest point is {:.3f} mm from it)", *lo_it));
  }
  if (!(farthest > start)) return core::make_error(core::ErrorCode::kInfeasible, "conformal layers: nothing of the region lies off the base surface");
  // n equal steps over [start, farthest], nearest the process's layer within [min, max].
  const double span = farthest - start;
  const double fewest = std::max(1.0, std::ceil(span / o.max_mm - 1e-9)), most = std::max(1.0, std::floor(span / o.min_mm + 1e-9));
  const double n_real = std::clamp(std::round(span / o.layer_mm), fewest, std::max(fewest, most));
  constexpr double kMaxLayers = 1e6;
  if (n_real > kMaxLayers) return core::make_error(core::ErrorCode::kUsage, fmt::format("conformal layers: {:.0f} layers; at most {:.0f}", n_real, kMaxLayers));
  const auto n = static_cast<std::size_t>(n_real);
  const double step = span / n_real;
  SectionContext ctx(fine, d, std::move(field));
  ctx.set_field_at([&base](Vec3 p) { return base.nearest(p).signed_mm; });
  const Frame plane = plane_frame(d, 0.0);

  SliceResult result;
  result.conformal_base = o.conformal_base;
  result.layers.resize(n);
  std::vector<std::uint32_t> open(n, 0);
  std::vector<std::string> failed(n);
  tbb::enumerable_thread_specific<SectionScratch> scratch;
  core::Progress progress("conformal layers", n);
  std::atomic<std::uint64_t> done{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& range) {
    SectionScratch& local = scratch.local();
    std::vector<std::uint32_t> candidates;
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const double level = start + (static_cast<double>(k) + 0.5) * step;
      candidates.clear();
      double guess = 0.0, weight = 0.0;
      for (std::uint32_t f = 0; f < fine.triangles.size(); ++f) {
        if (ctx.face_min(f) > level || ctx.face_max(f) < level) continue;
        candidates.push_back(f);
        guess += core::dot(fine.corner(f, 0), d), weight += 1.0;
      }
      Layer& layer = result.layers[k];
      layer.index = static_cast<std::uint32_t>(k);
      layer.below_mm = layer.above_mm = step / 2.0;
      layer.min_thickness_mm = layer.max_thickness_mm = step;
      SectionResult s = section(ctx, level, plane, candidates, local);
      layer.polygons = std::move(s.polygons);
      layer.area_mm2 = s.area_mm2;
      open[k] = s.open_chains;
      layer.conformal.emplace();
      layer.conformal->level_mm = level;
      failed[k] = lift_layer(base, plane, weight > 0.0 ? guess / weight : 0.0, layer);
    }
    done += range.size();
    if (tbb::this_task_arena::current_thread_index() == 0) progress.update(done);
  });
  for (const std::string& f : failed) {
    if (!f.empty()) return core::make_error(core::ErrorCode::kInfeasible, f);
  }
  if (step < o.min_mm - 1e-9 || step > o.max_mm + 1e-9) result.limit_violations = static_cast<std::uint32_t>(n);
  while (!result.layers.empty() && result.layers.back().polygons.empty()) result.layers.pop_back();
  for (std::size_t k = 0; k < result.layers.size(); ++k) {
    result.open_chains += open[k];
    result.total_area_mm2 += result.layers[k].area_mm2;
    result.volume_estimate_mm3 += result.layers[k].area_mm2 * step;
  }
  return result;
}

}  // namespace detail
}  // namespace polyaxis::slicing
