#include "sequence.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "polyaxis/geom2d/clip.h"

namespace polyaxis::planner::detail {
namespace {

using core::Vec3;

// Planes closer than this to parallel (sine of the angle between their normals) are parallel.
constexpr double kParallelSin = 1e-3;

// A layer's C-space contour: its polygons grown by the head's radius, as rings in mm in the layer's
// (u, v) frame, and a bounding sphere.
struct CContour {
  slicing::Frame frame;
  double low = 0.0, high = 0.0;  // the layer's slab along d
  std::vector<std::vector<std::array<double, 2>>> rings;
  std::vector<geom2d::Ring> integer_rings;
  double area_mm2 = 0.0;
  Vec3 centre;
  double radius = 0.0;
};

CContour grow(const slicing::Layer& layer, double head_radius_mm) {
  CContour c;
  c.frame = layer.frame;
  c.low = layer.height_mm - layer.below_mm, c.high = layer.height_mm + layer.above_mm;
  if (layer.conformal) c.low = layer.conformal->low_mm - layer.below_mm, c.high = layer.conformal->high_mm + layer.above_mm;  // the curved slab
  const std::vector<geom2d::Polygon> grown = geom2d::offset(layer.polygons, head_radius_mm);
  c.integer_rings = geom2d::rings_of(grown);
  c.area_mm2 = geom2d::area_mm2(grown);
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  for (const geom2d::Ring& ring : c.integer_rings) {
    auto& out = c.rings.emplace_back();
    for (const geom2d::Point& p : ring) {
      const double u = geom2d::to_mm(p.x), v = geom2d::to_mm(p.y);
      out.push_back({u, v});
      u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v);
    }
  }
  if (c.rings.empty()) return c;
  c.centre = layer.frame.to_world(0.5 * (u0 + u1), 0.5 * (v0 + v1));
  c.radius = 0.5 * std::hypot(u1 - u0, v1 - v0);
  return c;
}

// The parameters along the line P + t·W (in C's plane, (u, v) coordinates) where it is inside C's
// rings (even-odd: the grown polygons do not overlap), as sorted [t0, t1] pairs.
std::vector<std::array<double, 2>> inside_intervals(const CContour& c, double pu, double pv, double wu, double wv) {
  std::vector<double> ts;
  for (const auto& ring : c.rings) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const auto& a = ring[i];
      const auto& b = ring[(i + 1) % ring.size()];
      // Solve P + t·W = A + s·(B − A), s in [0, 1).
      const double ex = b[0] - a[0], ey = b[1] - a[1];
      const double den = wu * ey - wv * ex;
      if (std::abs(den) < 1e-15) continue;
      const double dx = a[0] - pu, dy = a[1] - pv;
      const double s = (wv * dx - wu * dy) / den;
      if (s < 0.0 || s >= 1.0) continue;
      ts.push_back((dx * ey - dy * ex) / den);
    }
  }
  std::sort(ts.begin(), ts.end());
  std::vector<std::array<double, 2>> out;
  for (std::size_t i = 0; i + 1 < ts.size(); i += 2) out.push_back({ts[i], ts[i + 1]});
  return out;
}

// True when the C-space contours A and B overlap in space.
bool interfere(const CContour& a, const CContour& b) {
  if (a.rings.empty() || b.rings.empty()) return false;
  if (core::norm(a.centre - b.centre) > a.radius + b.radius) return false;
  const Vec3 na = a.frame.d, nb = b.frame.d;
  const Vec3 w = core::cross(na, nb);
  const double s = core::norm(w);
  if (s < kParallelSin) {
    // Parallel planes: the same slab, then the grown polygons overlap on it.
    const double sign = core::dot(na, nb) > 0.0 ? 1.0 : -1.0;
    const double off = core::dot(b.frame.origin - a.frame.origin, na);  // b's plane above a's, along a's d
    double lo = off + sign * (b.low - core::dot(b.frame.origin, nb)), hi = off + sign * (b.high - core::dot(b.frame.origin, nb));
    if (lo > hi) std::swap(lo, hi);
    const double a_lo = a.low - core::dot(a.frame.origin, na), a_hi = a.high - core::dot(a.frame.origin, na);
    if (hi <= a_lo || lo >= a_hi) return false;
    std::vector<geom2d::Ring> rings = a.integer_rings;
    for (const auto& ring : b.rings) {
      geom2d::Ring r;
      for (const auto& p : ring) {
        const Vec3 q = b.frame.to_world(p[0], p[1]) - a.frame.origin;
        r.push_back({geom2d::to_units(core::dot(q, a.frame.u)), geom2d::to_units(core::dot(q, a.frame.v))});
      }
      if (sign < 0.0) std::reverse(r.begin(), r.end());  // seen from a's side the orientation flips
      rings.push_back(std::move(r));
    }
    const double together = geom2d::area_mm2(geom2d::union_rings(rings, geom2d::FillRule::kNonZero));
    return together < a.area_mm2 + b.area_mm2 - 1e-6 * (a.area_mm2 + b.area_mm2);
  }
  // The line where the planes meet: P0 + t·W.
  const double ha = core::dot(a.frame.origin, na), hb = core::dot(b.frame.origin, nb), c = core::dot(na, nb);
  const Vec3 p0 = (na * (ha - hb * c) + nb * (hb - ha * c)) / (1.0 - c * c);
  const Vec3 dir = w / s;
  auto in = [&](const CContour& k) {
    const Vec3 q = p0 - k.frame.origin;
    return inside_intervals(k, core::dot(q, k.frame.u), core::dot(q, k.frame.v), core::dot(dir, k.frame.u), core::dot(dir, k.frame.v));
  };
  const auto ia = in(a), ib = in(b);
  for (const auto& x : ia) {
    for (const auto& y : ib) {
      if (x[0] < y[1] && y[0] < x[1]) return true;
    }
  }
  return false;
}

// For each region (by position in REGIONS), the positions of its ancestors: its father, the regions
// its base rests on, theirs, and so on.
std::vector<std::vector<std::size_t>> ancestors(const std::vector<PlanRegion>& regions) {
  std::map<std::uint32_t, std::size_t> at;
  for (std::size_t i = 0; i < regions.size(); ++i) at[regions[i].id] = i;
  std::vector<std::vector<std::size_t>> out(regions.size());
  for (std::size_t i = 0; i < regions.size(); ++i) {
    // Depth-first over the parent and the regions the base rests on.
    std::vector<std::size_t> todo{i};
    while (!todo.empty()) {
      const PlanRegion& r = regions[todo.back()];
      todo.pop_back();
      std::vector<std::uint32_t> below = r.rests_on;
      if (r.parent) below.push_back(*r.parent);
      for (const std::uint32_t b : below) {
        if (!at.count(b) || at[b] == i || std::find(out[i].begin(), out[i].end(), at[b]) != out[i].end()) continue;
        out[i].push_back(at[b]);
        todo.push_back(at[b]);
      }
    }
  }
  return out;
}

// Every interfering pair of layers whose regions are not one the other's ancestor.
std::vector<std::vector<std::uint32_t>> interference(const std::vector<slicing::Layer>& layers, const std::vector<std::size_t>& region_pos,
                                                     const std::vector<PlanRegion>& regions, double head_radius_mm) {
  const auto anc = ancestors(regions);
  auto related = [&](std::size_t r1, std::size_t r2) {
    return r1 == r2 || std::find(anc[r1].begin(), anc[r1].end(), r2) != anc[r1].end() ||
           std::find(anc[r2].begin(), anc[r2].end(), r1) != anc[r2].end();
  };
  std::vector<std::vector<std::uint32_t>> with(layers.size());
  bool any_pair = false;
  for (std::size_t i = 0; i < regions.size() && !any_pair; ++i) {
    for (std::size_t j = i + 1; j < regions.size() && !any_pair; ++j) any_pair = !related(i, j);
  }
  if (!any_pair) return with;
  std::vector<CContour> grown(layers.size());
  tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t i) { grown[i] = grow(layers[i], head_radius_mm); });
  tbb::parallel_for(std::size_t{0}, layers.size(), [&](std::size_t i) {
    for (std::size_t j = 0; j < layers.size(); ++j) {
      if (!related(region_pos[i], region_pos[j]) && interfere(grown[i], grown[j])) with[i].push_back(static_cast<std::uint32_t>(j));
    }
  });
  return with;
}

}  // namespace

namespace {

// The layers of each region (by position in REGIONS) in layer order.
struct RegionLayers {
  std::map<std::uint32_t, std::size_t> pos_of;     // region id -> position in REGIONS
  std::vector<std::size_t> region_pos;             // per layer
  std::vector<std::vector<std::uint32_t>> layers;  // per region position
};

RegionLayers index_layers(const std::vector<std::uint32_t>& region_of_layer, const std::vector<PlanRegion>& regions, Sequence& out) {
  RegionLayers rl;
  for (std::size_t i = 0; i < regions.size(); ++i) rl.pos_of[regions[i].id] = i;
  rl.region_pos.resize(region_of_layer.size());
  rl.layers.resize(regions.size());
  for (std::size_t i = 0; i < region_of_layer.size(); ++i) {
    rl.region_pos[i] = rl.pos_of.count(region_of_layer[i]) ? rl.pos_of[region_of_layer[i]] : 0;
    out.records[i].region = region_of_layer[i];
    out.records[i].region_layer = static_cast<std::uint32_t>(rl.layers[rl.region_pos[i]].size() + 1);
    rl.layers[rl.region_pos[i]].push_back(static_cast<std::uint32_t>(i));
  }
  return rl;
}

// Levels (Rule 2): regions in build order, layers in layer order.
void assign_levels(const RegionLayers& rl, const std::vector<std::vector<std::uint32_t>>& with, Sequence& out) {
  std::vector<char> assigned(with.size(), 0);
  for (const auto& ids : rl.layers) {
    std::uint32_t previous = 0;
    for (const std::uint32_t i : ids) {
      assigned[i] = 1;
      if (with[i].empty()) continue;
      std::uint32_t level = 0;
      for (const std::uint32_t j : with[i]) {
        const std::uint32_t l = out.records[j].level;
        if (assigned[j] && l > previous && (level == 0 || l < level)) level = l;
      }
      out.records[i].level = previous = level ? level : previous + 1;
      auto& list = out.records[i].interferes_with;
      list.assign(with[i].begin(), with[i].begin() + static_cast<std::ptrdiff_t>(std::min(with[i].size(), kMaxListedInterference)));
      out.records[i].interferences = static_cast<std::uint32_t>(with[i].size());
    }
  }
}

// Order (Rules 3–4, children after what they rest on). Without INTERLEAVE every layer is taken as
// level 0.
void build_order(const RegionLayers& rl, const std::vector<PlanRegion>& regions, bool interleave, Sequence& out) {
  const std::size_t n = out.records.size();
  auto level = [&](std::uint32_t i) { return interleave ? out.records[i].level : 0u; };
  // The lowest level > 0 among each region's layers from position k on (0: none).
  std::vector<std::vector<std::uint32_t>> lowest_from(regions.size());
  for (std::size_t r = 0; r < regions.size(); ++r) {
    lowest_from[r].assign(rl.layers[r].size() + 1, 0);
    for (std::size_t k = rl.layers[r].size(); k-- > 0;) {
      const std::uint32_t l = level(rl.layers[r][k]), after = lowest_from[r][k + 1];
      lowest_from[r][k] = l == 0 ? after : (after == 0 ? l : std::min(l, after));
    }
  }
  std::vector<std::size_t> next(regions.size(), 0);
  auto complete = [&](std::size_t r) { return next[r] == rl.layers[r].size(); };
  // A region is open once its father and every region its base rests on are complete.
  auto open = [&](std::size_t r) {
    if (complete(r)) return false;
    std::vector<std::uint32_t> below = regions[r].rests_on;
    if (regions[r].parent) below.push_back(*regions[r].parent);
    return std::all_of(below.begin(), below.end(), [&](std::uint32_t b) { return !rl.pos_of.count(b) || complete(rl.pos_of.at(b)); });
  };
  std::optional<std::size_t> current;
  out.order.reserve(n);
  while (out.order.size() < n) {
    std::uint32_t pending = 0;  // the lowest level still to build among the open regions
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const std::uint32_t l = open(r) ? lowest_from[r][next[r]] : 0;
      if (l && (!pending || l < pending)) pending = l;
    }
    auto next_level = [&](std::size_t r) { return level(rl.layers[r][next[r]]); };
    auto buildable = [&](std::size_t r) { return open(r) && (next_level(r) == 0 || next_level(r) <= pending); };
    std::optional<std::size_t> pick;
    const char* rule = kRuleLevel;
    if (current && buildable(*current) && next_level(*current) == 0) {
      pick = current, rule = kRuleContinue;
    } else {
      // The pending level first, in region order; then a region's layers that interfere with none.
      for (std::size_t r = 0; r < regions.size() && !pick; ++r) {
        if (buildable(r) && next_level(r) == pending) pick = r;
      }
      for (std::size_t r = 0; r < regions.size() && !pick; ++r) {
        if (buildable(r)) pick = r;
      }
    }
    if (!pick) break;  // no open region: a region whose father is missing (cannot happen with a tree)
    const std::uint32_t i = rl.layers[*pick][next[*pick]];
    if (rule != kRuleContinue) {
      if (next[*pick] == 0) {
        rule = regions[*pick].parent ? kRuleFather : kRuleStart;
      } else if (level(i) == 0) {
        rule = kRuleContinue;
      }
    }
    out.records[i].rule = rule;
    out.order.push_back(i);
    ++next[*pick];
    current = pick;
  }
  // A region left out (its father missing from REGIONS) goes last, in order.
  for (std::size_t r = 0; r < regions.size(); ++r) {
    for (std::size_t k = next[r]; k < rl.layers[r].size(); ++k) {
      out.records[rl.layers[r][k]].rule = kRuleContinue;
      out.order.push_back(rl.layers[r][k]);
    }
  }
}

}  // namespace

Sequence sequence_layers(const std::vector<slicing::Layer>& layers, const std::vector<std::uint32_t>& region_of_layer,
                         const std::vector<PlanRegion>& regions, double head_radius_mm, bool interleave) {
  Sequence out;
  out.records.resize(layers.size());
  const RegionLayers rl = index_layers(region_of_layer, regions, out);
  assign_levels(rl, interference(layers, rl.region_pos, regions, head_radius_mm), out);
  build_order(rl, regions, interleave, out);
  return out;
}

}  // namespace polyaxis::planner::detail
