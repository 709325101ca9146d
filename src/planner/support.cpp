#include "support.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <tuple>

#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::planner::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxSupportAngleDeg = 89.0;  // tan() of the grown angle stays finite
// A sliver of overhang smaller than this is the polygonal sections disagreeing along a wall at
// exactly the self-supporting angle, not material hanging in the air.
constexpr double kPieceNoiseMm2 = 1e-3;
// A layer within this of the table's top, built within kUprightCos of +Z, stands on the table.
constexpr double kOnTableMm = 1e-6;
constexpr double kUprightCos = 1e-9;
// Two layers whose normals' dot product reaches this are parallel (planar slicing's are exactly).
constexpr double kParallelCos = 1.0 - 1e-12;

double angle_deg(Vec3 a, Vec3 b) {
  const double c = core::dot(core::normalized(a), core::normalized(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi;
}

// The unsupported area of LAYER over BELOW (the rings bounding what holds it, in the layer's (u, v)
// frame, T mm under it; see PlanOptions' comment in plan.h); the unsupported pieces are appended
// to PIECES.
double unsupported_area(const std::vector<geom2d::Ring>& below, double t, const slicing::Layer& layer,
                        const toolpath::LayerToolpaths& paths, double alpha_deg, double bead_mm, double max_step_mm,
                        std::vector<geom2d::Polygon>& pieces) {
  const double base_grow = t * std::tan(alpha_deg * kPi / 180.0);
  const auto overhang = geom2d::difference_rings(geom2d::rings_of(layer.polygons), geom2d::rings_of(geom2d::offset_rings(below, base_grow)));
  double total = 0.0;
  std::map<int, std::vector<geom2d::Ring>> grown_by_angle;  // the layer below grown, per tilt (0.1° steps)
  for (const geom2d::Polygon& piece : overhang) {
    const double piece_area = geom2d::area_mm2(piece);
    if (piece_area <= kPieceNoiseMm2) continue;
    // Largest torch tilt of the surface-contour points over this piece (within a bead of its box).
    std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
    for (const auto& q : piece.outer) x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
    const std::int64_t margin = geom2d::to_units(bead_mm);
    double tilt = 0.0;
    for (const toolpath::Path& path : paths.paths) {
      if (!path.surface_contour) continue;
      for (const toolpath::PathPoint& p : path.points) {
        const Vec3 rel = p.position_mm - layer.frame.origin;
        const std::int64_t u = geom2d::to_units(core::dot(rel, layer.frame.u)), v = geom2d::to_units(core::dot(rel, layer.frame.v));
        if (u < x0 - margin || u > x1 + margin || v < y0 - margin || v > y1 + margin) continue;
        tilt = std::max(tilt, angle_deg(p.tool_axis, layer.frame.d));
      }
    }
    if (tilt <= 0.0) {
      total += piece_area;
      pieces.push_back(piece);
      continue;
    }
    const int key = static_cast<int>(std::floor(std::min(alpha_deg + tilt, kMaxSupportAngleDeg) * 10.0));  // rounded down: conservative
    auto it = grown_by_angle.find(key);
    if (it == grown_by_angle.end()) {
      it = grown_by_angle.emplace(key, geom2d::rings_of(geom2d::offset_rings(below, tilted_step_mm(t, key / 10.0, alpha_deg, max_step_mm)))).first;
    }
    std::vector<geom2d::Polygon> left = geom2d::difference_rings(geom2d::rings_of({piece}), it->second);
    total += geom2d::area_mm2(left);
    pieces.insert(pieces.end(), left.begin(), left.end());
  }
  return total;
}

// Conformal LAYER's contour carried BY_MM down the distance's gradient (each point less its axis
// times BY_MM: the gradient's lines are straight), seen along the layer's d in its frame's (u, v).
// Unlike the footprint on the base, it does not fold where the base ends (a rim, whose gradient
// lines fan out from one edge and would all land on it).
std::vector<geom2d::Polygon> lowered(const slicing::Layer& layer, double by_mm) {
  const slicing::ConformalLayer& c = *layer.conformal;
  std::vector<geom2d::Ring> rings;
  for (std::size_t r = 0; r < c.contours.size() && r < c.axes.size(); ++r) {
    geom2d::Ring ring;
    for (std::size_t i = 0; i < c.contours[r].size() && i < c.axes[r].size(); ++i) {
      const Vec3 q = c.contours[r][i] - c.axes[r][i] * by_mm - layer.frame.origin;
      ring.push_back({geom2d::to_units(core::dot(q, layer.frame.u)), geom2d::to_units(core::dot(q, layer.frame.v))});
    }
    rings.push_back(std::move(ring));
  }
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

// The regions built before a region, sectioned along its direction (contexts made on first use, for
// one region at a time).
class BuiltBefore {
 public:
  BuiltBefore(const std::vector<PlanRegion>& regions) : regions_(regions) {}

  // The material of the regions before REGION_INDEX (build order) on the plane of FRAME, in its (u, v),
  // as the rings of its sections (overlapping where regions meet); of prebuilt regions on the plane
  // PREBUILT_DROP_MM lower.
  std::vector<geom2d::Ring> section(std::size_t region_index, const slicing::Frame& frame, double prebuilt_drop_mm) {
    if (region_index != region_) contexts_.clear(), region_ = region_index;  // layers come region by region
    std::vector<geom2d::Ring> rings;
    const double h = core::dot(frame.origin, frame.d);
    for (std::size_t q = 0; q < region_index; ++q) {
      auto& ctx = contexts_[q];
      if (!ctx) ctx = std::make_unique<slicing::SectionContext>(regions_[q].mesh, frame.d);
      const double hq = regions_[q].prebuilt ? h - prebuilt_drop_mm : h;
      if (hq < ctx->min_height() || hq > ctx->max_height()) continue;
      candidates_.clear();
      for (std::uint32_t f = 0; f < regions_[q].mesh.triangles.size(); ++f) {
        if (ctx->face_min(f) <= hq && ctx->face_max(f) >= hq) candidates_.push_back(f);
      }
      // (u, v) do not change along d: the frame serves the lower plane too.
      const slicing::SectionResult s = slicing::section(*ctx, hq, frame, candidates_, scratch_);
      for (geom2d::Ring& r : geom2d::rings_of(s.polygons)) rings.push_back(std::move(r));
    }
    return rings;
  }

 private:
  const std::vector<PlanRegion>& regions_;
  std::size_t region_ = SIZE_MAX;  // the region the contexts are for (its direction)
  std::map<std::size_t, std::unique_ptr<slicing::SectionContext>> contexts_;  // by earlier region
  std::vector<std::uint32_t> candidates_;
  slicing::SectionScratch scratch_;
};

}  // namespace

double tilted_step_mm(double t_mm, double tilted_deg, double alpha_deg, double max_step_mm) {
  const double plain = t_mm * std::tan(alpha_deg * kPi / 180.0);
  const double tilted = t_mm * std::tan(std::min(tilted_deg, kMaxSupportAngleDeg) * kPi / 180.0);
  return std::max(plain, std::min(tilted, max_step_mm));
}

void check_support(Plan& plan, const process::ProcessConfig& process) {
  const auto& ls = plan.layers.layers;
  plan.layer_reports.resize(ls.size());
  std::map<std::uint32_t, std::size_t> index_of;  // region id -> build order
  for (std::size_t i = 0; i < plan.placed_regions.size(); ++i) index_of[plan.placed_regions[i].id] = i;
  BuiltBefore built(plan.placed_regions);
  core::Progress progress("support", ls.size());
  std::map<std::uint32_t, std::size_t> previous_of_region;  // region id -> its latest layer so far
  for (std::size_t k = 0; k < ls.size(); ++k) {
    progress.update(k);
    LayerReport& r = plan.layer_reports[k];
    r.index = ls[k].index;
    r.region = plan.region_of_layer[k];
    const Vec3 layer_d = ls[k].frame.d;
    r.height_mm = ls[k].height_mm;
    r.thickness_mm = ls[k].thickness_mm();
    std::tie(r.min_thickness_mm, r.max_thickness_mm) = ls[k].thickness_range();
    r.area_mm2 = ls[k].area_mm2;
    const toolpath::LayerToolpaths& lt = plan.toolpaths[k];
    r.paths = static_cast<std::uint32_t>(lt.paths.size());
    for (const auto& path : lt.paths) {
      for (const auto& p : path.points) {
        if (!p.deposit) continue;
        const double tilt = angle_deg(p.tool_axis, layer_d);
        r.max_tilt_deg = std::max(r.max_tilt_deg, tilt);
        if (tilt > kTiltedDeg) ++r.tilted_points;
      }
    }
    r.turned_points = lt.axes_turned;
    r.eased_points = lt.axes_eased;
    const bool on_plate = layer_d.z > 1.0 - kUprightCos && std::abs(ls[k].height_mm - ls[k].below_mm) <= kOnTableMm;
    r.tilt_rule = on_plate ? kTiltOnPlate
                           : (lt.axes_eased > 0 ? kTiltEased : (lt.axes_turned > 0 ? kTiltClearance : (r.tilted_points > 0 ? kTiltOverhang : kTiltNormal)));
    const std::size_t region_index = index_of.count(r.region) ? index_of[r.region] : 0;
    // The layer below is the region's previous layer (brothers' layers may come between).
    const auto seen = previous_of_region.find(r.region);
    const bool first = seen == previous_of_region.end();
    const std::size_t below_k = first ? 0 : seen->second;
    previous_of_region[r.region] = k;
    // The first region's first layer stands on the table, and so does any region's first layer
    // built upright from the table's top (Z = 0 after placement).
    const bool on_table = layer_d.z > 1.0 - kUprightCos && ls[k].height_mm - ls[k].below_mm <= kOnTableMm;
    if (first && (region_index == 0 || on_table)) continue;
    const double alpha = process.self_supporting_deg, bead = process.bead_width_mm;
    const double max_step = process.max_step_bead_share * bead;
    double t = r.thickness_mm;
    std::vector<geom2d::Polygon> below;
    if (!first) {
      const slicing::Layer& under = ls[below_k];
      if (core::dot(under.frame.d, layer_d) >= kParallelCos) {
        t = ls[k].height_mm - under.height_mm, below = under.polygons;
      } else {
        // Tilted layers: the layer below seen along this one's normal, at its least thickness.
        t = ls[k].thickness_range().first, below = slicing::project(under.polygons, under.frame, ls[k].frame);
      }
    }
    std::vector<geom2d::Polygon> pieces;
    if (ls[k].conformal) {
      // Conformal layers: the first stands on the base, every point of it its level from the base
      // along the gradient. Each later one is carried down the gradient onto the level of the one
      // below (lowered()) and compared there with that layer's section, both seen along d.
      if (first) continue;
      const slicing::Layer& under = ls[below_k];
      slicing::Layer down = ls[k];
      const bool carried = under.conformal && !down.conformal->axes.empty();
      down.polygons = carried ? lowered(down, down.conformal->level_mm - under.conformal->level_mm) : down.conformal->footprint;
      const std::vector<geom2d::Polygon>& held = carried ? under.polygons : (under.conformal ? under.conformal->footprint : under.polygons);
      const double area = unsupported_area(geom2d::rings_of(held), ls[k].thickness_range().first, down, toolpath::LayerToolpaths{}, alpha, bead, max_step, pieces);
      if (area >= kUnsupportedNoiseMm2) r.unsupported_area_mm2 = area, r.unsupported = std::move(pieces);
      plan.unsupported_area_mm2 += r.unsupported_area_mm2;
      continue;
    }
    double area = first ? r.area_mm2 : unsupported_area(geom2d::rings_of(below), t, ls[k], lt, alpha, bead, max_step, pieces);
    if (area >= kUnsupportedNoiseMm2 && region_index > 0) {
      // What the earlier regions hold one layer below this one; a prebuilt part holds up the layer
      // wherever it comes within the least thickness under the layer's bottom (the planner trims
      // the layers above it to that, plan.cpp trim_over_prebuilt, and the bead fills the pocket).
      slicing::Frame under = ls[k].frame;
      under.origin = under.origin - under.d * t;
      const double prebuilt_drop = ls[k].below_mm + process.layer_min_mm - t;
      std::vector<geom2d::Ring> rings = geom2d::rings_of(below);
      for (geom2d::Ring& ring : built.section(region_index, under, prebuilt_drop)) rings.push_back(std::move(ring));
      pieces.clear();
      area = unsupported_area(geom2d::union_boundary(rings, geom2d::FillRule::kNonZero), t, ls[k], lt, alpha, bead, max_step, pieces);
    }
    if (area >= kUnsupportedNoiseMm2) r.unsupported_area_mm2 = area, r.unsupported = std::move(pieces);
    plan.unsupported_area_mm2 += r.unsupported_area_mm2;
  }
  // A region is support-free only when the layer check agrees with the region's own flag.
  for (PlanRegion& region : plan.placed_regions) {
    for (const LayerReport& r : plan.layer_reports) {
      if (r.region == region.id && r.unsupported_area_mm2 > 0.0) region.support_free = false;
    }
  }
}

}  // namespace polyaxis::planner::detail
