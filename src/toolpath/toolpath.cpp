// Per-layer toolpaths (SPEC §2.5): perimeters as inward offsets, zigzag or contour-parallel fill,
// thin features reported, greedy nearest-start ordering with golden-angle seams, and tool axes
// after Kapil et al. Eq. 1-3 (overhang.cpp).
#include "polyaxis/toolpath/toolpath.h"

#include <fmt/format.h>
#include "core/arena.h"
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>

#include "drape.h"
#include "overhang.h"
#include "polyaxis/core/progress.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/geom2d/clip.h"
#include "gap_fill.h"
#include "zigzag.h"

namespace polyaxis::toolpath {
namespace {

using core::ErrorCode;
using core::make_error;
using geom2d::Int128;
using geom2d::Point;
using geom2d::Polygon;
using geom2d::Ring;

constexpr double kPi = 3.14159265358979323846;
// Two layers whose normals' dot product reaches this are parallel (planar slicing's are exactly).
constexpr double kParallelCos = 1.0 - 1e-12;
// Seams turn by the golden angle from layer to layer: no two layers in a long run share a direction.
const double kGoldenAngleRad = kPi * (3.0 - std::sqrt(5.0));
// Two layers share a build direction when their unit normals differ by less than this (unitless).
constexpr double kSameDirection = 1e-9;
// Bound on perimeters per island: more than this is a units mistake, not a plan.
constexpr int kMaxPerimeters = 10'000;
// An island's outline points within this of the chord between the points kept either side of them
// are dropped before its paths are made (geom2d::simplified), mm. A plane crossing a fine mesh gives
// a point on every edge it crosses, and one on a split quad's diagonal that lies all but on the
// line of its neighbours; each offset and boolean of the island (a dozen per island) costs in
// proportion to the points. This halves them on finely tessellated parts (torus_100k: toolpaths
// 0.58 -> 0.32 s), for a change in the paths far below a bead's placement and five times below
// the program's chordal tolerance (0.01 mm). The layer's own section (the support check, the
// tilted slicing's centroids) is left exact.
constexpr double kOutlineSimplifyMm = 0.002;

// A path before it is placed in the layer's order: points in the layer's (u, v) units.
struct Candidate {
  PathKind kind = PathKind::kPerimeter;
  std::uint32_t perimeter_index = 0;
  bool surface_contour = false;
  bool closed = true;
  bool fixed_start = false;  // a perimeter whose seam is already chosen
  Ring points;
  bool gap_fill = false;
};

// Candidates of one island in the groups they run in: perimeter 0, 1, ..., then fill.
using Island = std::vector<std::vector<Candidate>>;

Int128 dist2(Point a, Point b) {
  const Int128 dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

std::size_t nearest_vertex(const Ring& ring, Point target) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < ring.size(); ++i) {
    if (dist2(ring[i], target) < dist2(ring[best], target)) best = i;
  }
  return best;
}

// The point seams are drawn towards on layer K: outside the layer's bounding box, in the
// direction k·(golden angle) from the centroid.
Point seam_target(const slicing::Layer& layer) {
  const geom2d::Centroid c = geom2d::centroid(layer.polygons);
  std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0, x1 = std::numeric_limits<std::int64_t>::min(), y1 = x1;
  for (const Polygon& p : layer.polygons) {
    for (const Point& q : p.outer) {
      x0 = std::min(x0, q.x);
      y0 = std::min(y0, q.y);
      x1 = std::max(x1, q.x);
      y1 = std::max(y1, q.y);
    }
  }
  const double reach_mm = std::hypot(geom2d::to_mm(x1 - x0), geom2d::to_mm(y1 - y0)) + 1.0;
  const double a = std::fmod(static_cast<double>(layer.index) * kGoldenAngleRad, 2.0 * kPi);
  return {geom2d::to_units(c.x + reach_mm * std::cos(a)), geom2d::to_units(c.y + reach_mm * std::sin(a))};
}

Ring rotated_to(const Ring& ring, std::size_t start) {
  Ring out(ring.begin() + static_cast<std::ptrdiff_t>(start), ring.end());
  out.insert(out.end(), ring.begin(), ring.begin() + static_cast<std::ptrdiff_t>(start));
  return out;
}

// Closed candidates, one per ring of OFFSET.
void add_rings(const std::vector<Polygon>& offset, PathKind kind, std::uint32_t index, bool outermost, bool fixed,
               std::vector<Candidate>& group) {
  for (const Polygon& p : offset) {
    if (p.outer.size() >= 3) group.push_back({kind, index, outermost, true, fixed, p.outer});
    for (const Ring& h : p.holes) {
      if (h.size() >= 3) group.push_back({kind, index, outermost, true, fixed, h});
    }
  }
}

// How far the start of C would be from CUR, given the freedom C has (squared units).
Int128 start_distance(const Candidate& c, Point cur) {
  if (c.closed && !c.fixed_start) return dist2(c.points[nearest_vertex(c.points, cur)], cur);
  if (c.closed) return dist2(c.points.front(), cur);
  return std::min(dist2(c.points.front(), cur), dist2(c.points.back(), cur));
}

// Orients C to start as near to CUR as its freedom allows.
void start_near(Candidate& c, Point cur) {
  if (c.closed && !c.fixed_start) {
    c.points = rotated_to(c.points, nearest_vertex(c.points, cur));
  } else if (!c.closed && dist2(c.points.back(), cur) < dist2(c.points.front(), cur)) {
    std::reverse(c.points.begin(), c.points.end());
  }
}

class LayerPlanner {
 public:
  // REST_ON (optional): the beads of the layer below in this layer's (u, v); gap fill is kept over them.
  LayerPlanner(const mesh::Mesh& mesh, const ToolpathOptions& o, const slicing::Layer& layer, const detail::FacetLocator* facets,
               const std::vector<Polygon>* rest_on = nullptr)
      : mesh_(mesh), o_(o), layer_(layer), facets_(facets), rest_on_(rest_on) {}

  LayerToolpaths run() {
    LayerToolpaths out;
    out.layer = layer_.index;
    if (layer_.polygons.empty()) return out;
    const Point target = seam_target(layer_);
    std::vector<Island> islands;
    for (const Polygon& outline : layer_.polygons) {
      Island island = plan_island(geom2d::simplified(outline, kOutlineSimplifyMm), out.thin);
      for (auto& group : island) {
        for (Candidate& c : group) {
          if (c.fixed_start) c.points = rotated_to(c.points, nearest_vertex(c.points, target));
        }
      }
      std::erase_if(island, [](const std::vector<Candidate>& g) { return g.empty(); });
      if (!island.empty()) islands.push_back(std::move(island));
    }
    emit(order(std::move(islands), target), out);
    return out;
  }

 private:
  double spacing_mm() const { return o_.bead_width_mm * (1.0 - o_.overlap); }

  Vec3 world(Point p) const { return layer_.frame.to_world(geom2d::to_mm(p.x), geom2d::to_mm(p.y)); }

  Island plan_island(const Polygon& polygon, std::vector<ThinRegion>& thin) const {
    const double w = o_.bead_width_mm, s = spacing_mm();
    const std::vector<Polygon> island{polygon};
    const std::vector<Polygon> first = geom2d::offset(island, -w / 2.0);
    std::vector<Candidate> gap = gap_fill(polygon, first, thin);
    Island groups;
    const auto n = static_cast<std::uint32_t>(o_.perimeters);
    std::vector<std::vector<Polygon>> rings;  // the perimeters' paths, up to the first that is empty
    for (std::uint32_t k = 0; k < n; ++k) {
      rings.push_back(k == 0 ? first : geom2d::offset(island, -(w / 2.0 + k * s)));
      if (rings.back().empty()) break;
      groups.emplace_back();
      add_rings(rings.back(), PathKind::kPerimeter, k, k == 0, true, groups.back());
    }
    if (!gap.empty()) groups.push_back(std::move(gap));
    if (std::vector<Candidate> between = gaps_between_perimeters(island, rings, thin); !between.empty()) groups.push_back(std::move(between));
    if (o_.fill == ToolpathOptions::kZigzag) {
      // The innermost perimeter's bead edge: lines s/2 inside it sit a full spacing from it.
      const std::vector<Polygon> region = geom2d::offset(island, -(w / 2.0 + n * s - s / 2.0));
      const double angle = (o_.fill_angle_deg + (layer_.index % 2 == 0 ? 0.0 : 90.0)) * kPi / 180.0;
      std::vector<Candidate> fill;
      for (const Polygon& piece : region) {
        // A piece narrower than the line spacing (what two perimeters leave of a wall a few beads
        // thick): zigzag lines would cross it in short strokes, leaving it bare between them where
        // they run nearly along it; one bead along its middle covers it.
        if (geom2d::offset({piece}, -s / 2.0).empty()) {
          std::vector<Ring> middle = detail::centre_lines(piece, w, kGapFillMinWidthBeads * w);
          for (Ring& line : middle) fill.push_back({PathKind::kFill, 0, false, false, false, std::move(line)});
          if (!middle.empty()) continue;
        }
        for (Ring& line : detail::zigzag(piece, angle, geom2d::to_units(s))) {
          fill.push_back({PathKind::kFill, 0, false, false, false, std::move(line)});
        }
      }
      groups.push_back(std::move(fill));
    } else if (o_.fill == ToolpathOptions::kContour) {
      for (std::uint32_t j = 0;; ++j) {
        const std::vector<Polygon> ring = geom2d::offset(island, -(w / 2.0 + (n + j) * s));
        if (ring.empty()) break;
        groups.emplace_back();
        add_rings(ring, PathKind::kFill, n + j, false, false, groups.back());
      }
    }
    return groups;
  }

  ThinRegion thin_region(const Polygon& piece, std::string what) const {
    const geom2d::Centroid c = geom2d::centroid({piece});
    return {layer_.index, layer_.frame.to_world(c.x, c.y), c.area, std::move(what)};
  }

  // The pieces of POLYGON that the first perimeter's bead (FIRST grown back by half a bead) does
  // not cover, or all of it when no perimeter fits: each laid as one bead along its middle (gap
  // fill, as open fill paths), and what no bead covers reported as thin.
  std::vector<Candidate> gap_fill(const Polygon& polygon, const std::vector<Polygon>& first, std::vector<ThinRegion>& thin) const {
    const double w = o_.bead_width_mm;
    if (first.empty()) return lay_middles({polygon}, fmt::format("island narrower than a bead ({} mm): no perimeter fits", w), thin);
    return lay_middles(uncovered({polygon}, first), fmt::format("feature narrower than a bead ({} mm): not deposited", w), thin);
  }

  // The pieces of AREA (at least kThinMinAreaBeads2 bead widths squared) that the beads along
  // PATHS (polygons' boundaries, each bead half a bead to either side) leave bare.
  std::vector<Polygon> uncovered(const std::vector<Polygon>& area, const std::vector<Polygon>& paths) const {
    const double w = o_.bead_width_mm, min_area = kThinMinAreaBeads2 * w * w;
    const auto covered = geom2d::offset(paths, w / 2.0 + kThinSlackMm);
    std::vector<Polygon> out;
    for (Polygon& piece : geom2d::difference_rings(geom2d::rings_of(area), geom2d::rings_of(covered))) {
      if (geom2d::area_mm2(piece) >= min_area) out.push_back(std::move(piece));
    }
    return out;
  }

  // Gap fill between perimeters: where perimeter K cannot follow perimeter K − 1 all the way (a
  // wall between 2K and 2K + 2 beads thick, a strip's end), the area inside perimeter K − 1's
  // bead that perimeter K's bead does not reach, each piece at least kGapFillMinWidthBeads wide
  // one bead along its middle as gap_fill's. The fill region starts inside the last perimeter and
  // lays its own narrow pieces.
  // RINGS: the perimeters' paths (plan_island), the last one empty where one did not fit.
  std::vector<Candidate> gaps_between_perimeters(const std::vector<Polygon>& island, const std::vector<std::vector<Polygon>>& rings,
                                                 std::vector<ThinRegion>& thin) const {
    const double w = o_.bead_width_mm, s = spacing_mm(), min_area = kThinMinAreaBeads2 * w * w;
    std::vector<Candidate> out;
    for (std::size_t k = 1; k < rings.size() + 1 && k < static_cast<std::size_t>(o_.perimeters); ++k) {
      if (rings[k - 1].empty()) break;
      const std::vector<Polygon> inside = geom2d::offset(island, -(w + static_cast<double>(k - 1) * s));  // perimeter K − 1's bead's inner edge
      if (inside.empty()) break;
      const std::vector<Polygon> none;
      const std::vector<Polygon>& next = k < rings.size() ? rings[k] : none;
      // Beads that do not overlap (s = w): perimeter K's bead lies inside INSIDE, so where their
      // areas agree no piece can be left (the common case: a wall every perimeter follows).
      if (s >= w && !next.empty() && geom2d::area_mm2(inside) - geom2d::area_mm2(geom2d::offset(next, w / 2.0)) < min_area) continue;
      // A gap narrower than a gap fill's bead may be is the beads' spread, as the fill leaves it
      // at its edges: neither laid nor reported.
      std::vector<Polygon> gaps = uncovered(inside, next);
      std::erase_if(gaps, [&](const Polygon& g) { return spread(g); });
      std::vector<Candidate> laid =
          lay_middles(gaps, fmt::format("gap between perimeters narrower than a bead ({} mm): not deposited", w), thin, true);
      for (Candidate& c : laid) out.push_back(std::move(c));
    }
    return out;
  }

  // Whether all of PIECE, a gap between beads, is narrower than a gap-fill bead may be: the beads'
  // spread, as the fill leaves it at its edges, neither laid nor reported.
  bool spread(const Polygon& piece) const { return geom2d::offset({piece}, -kGapFillMinWidthBeads * o_.bead_width_mm / 2.0).empty(); }

  // Each of PIECES laid as one bead along its middle (open fill paths marked gap fill; kept over
  // REST_ON when given), what no bead covers reported as thin with WHAT (but for the beads' spread
  // when BETWEEN_BEADS: a gap between perimeters narrows to it where a wall's thickness does).
  // A branch that the middle does not follow (the skeleton's side branches, a fin's channel off
  // the loop around a tube's channel) gets its own bead along its middle, once: what the first
  // beads leave of the piece is laid as a piece of its own.
  std::vector<Candidate> lay_middles(const std::vector<Polygon>& pieces, const std::string& what, std::vector<ThinRegion>& thin,
                                     bool between_beads = false) const {
    const double w = o_.bead_width_mm, min_area = kThinMinAreaBeads2 * w * w;
    std::vector<Candidate> out;
    for (const Polygon& piece : pieces) {
      std::vector<Ring> lines = middles(piece);
      if (lines.empty()) {
        thin.push_back(thin_region(piece, what));
        continue;
      }
      std::vector<Polygon> left = left_by(piece, lines);
      const std::size_t first_lines = lines.size();
      for (const Polygon& branch : left) {
        if (geom2d::area_mm2(branch) < min_area) continue;
        for (Ring& line : middles(branch)) lines.push_back(std::move(line));
      }
      if (lines.size() > first_lines) left = left_by(piece, lines);
      for (const Polygon& bare : left) {
        if (geom2d::area_mm2(bare) >= min_area && !(between_beads && spread(bare))) thin.push_back(thin_region(bare, what));
      }
      for (Ring& line : lines) out.push_back({PathKind::kFill, 0, false, false, false, std::move(line), true});
    }
    return out;
  }

  // One bead's centre lines along the middle of PIECE, kept over REST_ON when given (none when the
  // options leave out gap fill).
  std::vector<Ring> middles(const Polygon& piece) const {
    const double w = o_.bead_width_mm;
    std::vector<Ring> lines;
    if (o_.gap_fill) lines = detail::centre_lines(piece, w, kGapFillMinWidthBeads * w);
    if (rest_on_ != nullptr && !lines.empty()) lines = detail::lines_within(lines, *rest_on_, w);
    return lines;
  }

  // What the beads along LINES leave of PIECE.
  std::vector<Polygon> left_by(const Polygon& piece, const std::vector<Ring>& lines) const {
    const auto laid = geom2d::sweep_open(lines, o_.bead_width_mm / 2.0 + kThinSlackMm);
    return geom2d::difference_rings(geom2d::rings_of({piece}), geom2d::rings_of(laid));
  }

  // Islands in greedy order of their nearest entry, and within each its groups in order, each
  // group greedily by the nearest start; from the seam target.
  std::vector<Candidate> order(std::vector<Island> islands, Point start) const {
    std::vector<Candidate> out;
    Point cur = start;
    std::vector<char> done(islands.size(), 0);
    for (std::size_t round = 0; round < islands.size(); ++round) {
      std::size_t best = islands.size();
      Int128 best_d = 0;
      for (std::size_t i = 0; i < islands.size(); ++i) {
        if (done[i]) continue;
        for (const Candidate& c : islands[i].front()) {
          const Int128 d = start_distance(c, cur);
          if (best == islands.size() || d < best_d) {
            best = i;
            best_d = d;
          }
        }
      }
      done[best] = 1;
      for (auto& group : islands[best]) {
        std::vector<char> used(group.size(), 0);
        for (std::size_t taken = 0; taken < group.size(); ++taken) {
          std::size_t pick = group.size();
          Int128 pick_d = 0;
          for (std::size_t j = 0; j < group.size(); ++j) {
            if (used[j]) continue;
            const Int128 d = start_distance(group[j], cur);
            if (pick == group.size() || d < pick_d) {
              pick = j;
              pick_d = d;
            }
          }
          used[pick] = 1;
          Candidate& c = group[pick];
          start_near(c, cur);
          cur = c.closed ? c.points.front() : c.points.back();
          out.push_back(std::move(c));
        }
      }
    }
    return out;
  }

  // Tool axes along CANDIDATE's points (one per point, closed paths without the repeat).
  std::vector<Vec3> axes(const Candidate& c) const {
    const Vec3 d = layer_.frame.d;
    std::vector<Vec3> out(c.points.size(), d);
    if (!o_.tilt_on_overhang || !c.surface_contour || facets_ == nullptr || facets_->empty()) return out;
    const double min_dot = -std::sin(o_.self_supporting_deg * kPi / 180.0);
    const std::size_t n = c.points.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Point a = c.points[i], b = c.points[(i + 1) % n];
      const double mu = 0.5 * (geom2d::to_mm(a.x) + geom2d::to_mm(b.x)), mv = 0.5 * (geom2d::to_mm(a.y) + geom2d::to_mm(b.y));
      // Kapil's p_i, p_{i+1} are points of the part's contour: take the direction of the contour
      // segment in the nearest facet, not the path's own step, which at the corners of an
      // offset ring can be a 1 nm rounding jog in any direction.
      const detail::FacetLocator::Nearest near = facets_->nearest(mu, mv);
      const Vec3 normal = core::normalized(mesh::face_area_vector(mesh_, near.face));
      const Vec3 tangent = layer_.frame.u * near.tu + layer_.frame.v * near.tv;
      out[i] = detail::torch_axis(normal, tangent, d, min_dot);
    }
    std::vector<Vec3> at;
    at.reserve(n);
    for (const Point& p : c.points) at.push_back(world(p));
    smooth_tool_axes(at, out, d, c.closed, o_.axis_window_mm, o_.max_axis_turn_deg_per_mm);
    return out;
  }

  // The indices of C's points less those within detail::kSamePointMm of the point kept before them (and,
  // on a closed path, of its first point, which closes it).
  static std::vector<std::size_t> distinct_points(const Candidate& c) {
    const double same = detail::kSamePointMm * geom2d::kUnitsPerMm;
    auto near = [&](Point a, Point b) { return std::hypot(static_cast<double>(a.x - b.x), static_cast<double>(a.y - b.y)) < same; };
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      if (kept.empty() || !near(c.points[i], c.points[kept.back()])) kept.push_back(i);
    }
    while (c.closed && kept.size() > 1 && near(c.points[kept.back()], c.points.front())) kept.pop_back();
    return kept;
  }

  void emit(std::vector<Candidate> ordered, LayerToolpaths& out) const {
    for (const Candidate& c : ordered) {
      Path path;
      path.kind = c.kind;
      path.layer = layer_.index;
      path.region = o_.region;
      path.perimeter_index = c.perimeter_index;
      path.surface_contour = c.surface_contour;
      path.gap_fill = c.gap_fill;
      const std::vector<Vec3> axis = axes(c);
      for (const std::size_t i : distinct_points(c)) path.points.push_back({world(c.points[i]), axis[i], !path.points.empty()});
      if (c.closed) path.points.push_back({world(c.points.front()), axis.front(), true});
      for (std::size_t i = 1; i < path.points.size(); ++i) {
        out.deposit_length_mm += core::norm(path.points[i].position_mm - path.points[i - 1].position_mm);
      }
      if (!out.paths.empty()) {
        const PathPoint& from = out.paths.back().points.back();
        const PathPoint& to = path.points.front();
        const double length = core::norm(to.position_mm - from.position_mm);
        if (length > 0.0) {
          Path travel;
          travel.kind = PathKind::kTravel;
          travel.layer = layer_.index;
          travel.region = o_.region;
          travel.points = {{from.position_mm, from.tool_axis, false}, {to.position_mm, to.tool_axis, false}};
          out.travel_length_mm += length;
          out.paths.push_back(std::move(travel));
        }
      }
      out.paths.push_back(std::move(path));
    }
  }

  const mesh::Mesh& mesh_;
  const ToolpathOptions& o_;
  const slicing::Layer& layer_;
  const detail::FacetLocator* facets_;
  const std::vector<Polygon>* rest_on_;
};

bool finite_positive(double x) { return std::isfinite(x) && x > 0.0; }

bool has_gap_fill(const LayerToolpaths& layer) {
  return std::any_of(layer.paths.begin(), layer.paths.end(), [](const Path& p) { return p.gap_fill; });
}

// What holds a gap-fill line of ABOVE: the centre lines of BELOW's beads seen along FRAME's normal,
// in FRAME's (u, v), grown by REACH_MM, and the gaps between the beads (BEAD wide) narrower than a
// gap fill's least width: those are the beads' spread, left unlaid below (lay_middles), and a bead
// over one rests on the beads to either side of it.
// Without them, a gap that widened from layer to layer was never filled, each layer's fill dropped
// for want of the one below, and a perimeter laid over the void at last had nothing under it (a
// bent tube's wall 2 to 3 beads thick). Of the runs of deposit that come within two beads of the
// box of ABOVE's gap-fill paths; overlapping polygons, whose union (nonzero rule) holds the lines.
std::vector<Polygon> beads_under(const LayerToolpaths& below, const slicing::Frame& frame, const LayerToolpaths& above, double bead,
                                 double reach_mm) {
  auto local = [&](Vec3 p) {
    const Vec3 r = p - frame.origin;
    return Point{geom2d::to_units(core::dot(r, frame.u)), geom2d::to_units(core::dot(r, frame.v))};
  };
  std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
  std::vector<Ring> lines;  // ABOVE's gap fill
  for (const Path& path : above.paths) {
    if (!path.gap_fill) continue;
    lines.emplace_back();
    for (const PathPoint& p : path.points) {
      const Point q = local(p.position_mm);
      x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
      lines.back().push_back(q);
    }
  }
  const std::int64_t margin = geom2d::to_units(2.0 * bead);
  std::vector<Ring> runs;
  Ring run;
  auto flush = [&] {  // kept when the run's box comes within the margin of the gap fill's
    std::int64_t a0 = INT64_MAX, b0 = INT64_MAX, a1 = INT64_MIN, b1 = INT64_MIN;
    for (const Point& q : run) a0 = std::min(a0, q.x), b0 = std::min(b0, q.y), a1 = std::max(a1, q.x), b1 = std::max(b1, q.y);
    if (run.size() >= 2 && a1 >= x0 - margin && a0 <= x1 + margin && b1 >= y0 - margin && b0 <= y1 + margin) runs.push_back(std::move(run));
    run.clear();
  };
  for (const Path& path : below.paths) {
    if (path.kind == PathKind::kTravel) continue;
    for (std::size_t i = 0; i < path.points.size(); ++i) {
      if (!path.points[i].deposit) {
        flush();
        continue;
      }
      if (run.empty() && i > 0) run.push_back(local(path.points[i - 1].position_mm));
      run.push_back(local(path.points[i].position_mm));
    }
    flush();
  }
  // The gaps, worked out on the beads within two beads of the lines only (the beads of a whole
  // layer, swept and offset, cost Clipper's hole nesting seconds a layer on a large part).
  const double closing = kGapFillMinWidthBeads * bead / 2.0 + kThinSlackMm;
  const std::vector<Ring> near = geom2d::clip_open(runs, geom2d::rings_of(geom2d::sweep_open(lines, 2.0 * bead)));
  const std::vector<Ring> beads = geom2d::rings_of(geom2d::sweep_open(near, bead / 2.0));
  const std::vector<Polygon> gaps =
      geom2d::difference_rings(geom2d::rings_of(geom2d::offset(geom2d::offset_rings(beads, closing), -closing)), beads);
  // Overlapping pieces: read under the nonzero rule (lines_within), as one.
  std::vector<Polygon> held = geom2d::sweep_open(runs, reach_mm);
  held.insert(held.end(), gaps.begin(), gaps.end());
  return held;
}

}  // namespace

core::Status validate(const ToolpathOptions& o) {
  if (!finite_positive(o.bead_width_mm)) return make_error(ErrorCode::kUsage, "bead width: must be a finite number > 0");
  if (o.perimeters < 0 || o.perimeters > kMaxPerimeters) {
    return make_error(ErrorCode::kUsage, fmt::format("perimeters: {} is not in [0, {}]", o.perimeters, kMaxPerimeters));
  }
  if (o.fill != ToolpathOptions::kZigzag && o.fill != ToolpathOptions::kContour && o.fill != ToolpathOptions::kNone) {
    return make_error(ErrorCode::kUsage, "fill: must be zigzag, contour or none");
  }
  if (!std::isfinite(o.fill_angle_deg)) return make_error(ErrorCode::kUsage, "fill angle: must be a finite number");
  if (!(o.overlap >= 0.0 && o.overlap < 1.0)) return make_error(ErrorCode::kUsage, "overlap: must be in [0, 1)");
  if (!(o.self_supporting_deg >= 0.0 && o.self_supporting_deg < 90.0)) {
    return make_error(ErrorCode::kUsage, "self-supporting angle: must be in [0, 90) degrees");
  }
  if (!(o.max_step_mm >= 0.0 && std::isfinite(o.max_step_mm))) return make_error(ErrorCode::kUsage, "max step: must be a finite number >= 0 mm");
  if (o.threads < 0) return make_error(ErrorCode::kUsage, "threads: must be >= 0");
  return {};
}

namespace {

core::Result<std::vector<LayerToolpaths>> toolpaths_in_arena(const mesh::Mesh& mesh, const slicing::SliceResult& slices,
                                                         const ToolpathOptions& options) {
  if (auto s = validate(options); !s) return s.error();
  const std::vector<slicing::Layer>& layers = slices.layers;
  std::vector<LayerToolpaths> result(layers.size());
  if (layers.empty()) return result;
  const Vec3 d = layers.front().frame.d;
  // Tilted layers (slicing::SliceOptions::tilted) each have their own direction.
  const bool shared = std::all_of(layers.begin(), layers.end(), [&](const slicing::Layer& l) { return core::norm(l.frame.d - d) < kSameDirection; });

  // Faces crossing each layer's plane (face_min < h <= face_max, the tie rule of section.h), by a
  // counting sort over the layers in height order.
  // Conformal layers take the distance's gradient as their axes (drape.h): no overhang tilt.
  const bool tilt = options.tilt_on_overhang && !mesh.triangles.empty() && !slices.conformal_base;
  std::optional<slicing::SectionContext> ctx;
  std::vector<std::uint32_t> start, bucket, slot_of_layer(layers.size());
  const mesh::EdgeTopology topology = tilt && !shared ? mesh::build_topology(mesh) : mesh::EdgeTopology{};
  if (tilt && shared) {
    ctx.emplace(mesh, d);
    std::vector<std::uint32_t> by_height(layers.size());
    std::iota(by_height.begin(), by_height.end(), 0u);
    std::stable_sort(by_height.begin(), by_height.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return layers[a].height_mm < layers[b].height_mm; });
    std::vector<double> heights(layers.size());
    for (std::size_t i = 0; i < by_height.size(); ++i) {
      heights[i] = layers[by_height[i]].height_mm;
      slot_of_layer[by_height[i]] = static_cast<std::uint32_t>(i);
    }
    auto range = [&](std::uint32_t f) {
      const auto lo = std::upper_bound(heights.begin(), heights.end(), ctx->face_min(f)) - heights.begin();
      const auto hi = std::upper_bound(heights.begin(), heights.end(), ctx->face_max(f)) - heights.begin();
      return std::pair<std::size_t, std::size_t>{static_cast<std::size_t>(lo), static_cast<std::size_t>(std::max(lo, hi))};
    };
    start.assign(layers.size() + 1, 0);
    const auto nf = static_cast<std::uint32_t>(mesh.triangles.size());
    for (std::uint32_t f = 0; f < nf; ++f) {
      const auto [lo, hi] = range(f);
      for (std::size_t k = lo; k < hi; ++k) ++start[k + 1];
    }
    for (std::size_t k = 0; k < layers.size(); ++k) start[k + 1] += start[k];
    bucket.resize(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t f = 0; f < nf; ++f) {
      const auto [lo, hi] = range(f);
      for (std::size_t k = lo; k < hi; ++k) bucket[fill[k]++] = f;
    }
  }

  core::Progress progress("toolpaths", layers.size());
  std::atomic<std::uint64_t> done{0};
  std::vector<std::string> failed(slices.conformal_base ? layers.size() : 0);
  // A conformal layer's warp, made once (the gap fill's second pass plans the layer again).
  std::vector<std::optional<detail::SurfaceWarp>> warps(slices.conformal_base ? layers.size() : 0);
  // Layer I's toolpaths, its gap fill kept over REST_ON when given (LayerPlanner).
  const std::vector<geom2d::Polygon> nothing;
  auto plan_layer = [&](std::size_t i, const std::vector<geom2d::Polygon>* rest_on) {
    std::optional<detail::FacetLocator> facets;
    std::optional<slicing::SectionContext> own;  // a tilted layer's direction
    std::vector<std::uint32_t> own_faces;
    if (tilt && shared) {
      const std::uint32_t k = slot_of_layer[i];
      const std::span<const std::uint32_t> faces(bucket.data() + start[k], start[k + 1] - start[k]);
      facets.emplace(*ctx, layers[i].height_mm, layers[i].frame, faces);
    } else if (tilt) {
      own.emplace(mesh, layers[i].frame.d, &topology);
      const double h = layers[i].height_mm;
      for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        if (own->face_min(f) < h && h <= own->face_max(f)) own_faces.push_back(f);  // as the shared buckets (section.h's tie rule)
      }
      facets.emplace(*own, h, layers[i].frame, own_faces);
    }
    if (slices.conformal_base) {
      // Conformal: the paths are made on the section warped to the surface's lengths, then draped.
      const double step = kDrapeStepBeads * options.bead_width_mm;
      if (!warps[i]) warps[i].emplace(*slices.conformal_base, layers[i], step);
      const detail::SurfaceWarp& warp = *warps[i];
      slicing::Layer warped = layers[i];
      warped.polygons = warp.warped(layers[i].polygons);
      // The beads below, seen along the layer's normal as its points are lifted, warped alike.
      std::optional<std::vector<geom2d::Polygon>> warped_rest;
      if (rest_on != nullptr) warped_rest = warp.warped(*rest_on);
      result[i] = LayerPlanner(mesh, options, warped, nullptr, warped_rest ? &*warped_rest : nullptr).run();
      failed[i] = detail::drape(*slices.conformal_base, layers[i], warp, step, result[i]);
      return;
    }
    result[i] = LayerPlanner(mesh, options, layers[i], facets ? &*facets : nullptr, rest_on).run();
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, layers.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) plan_layer(i, i == 0 && !options.gap_fill_first_layer ? &nothing : nullptr);
    done += r.size();
    if (tbb::this_task_arena::current_thread_index() == 0) progress.update(done);
  });
  // Gap fill above the first layer is kept within max(t·tan α, max_step_mm) of the beads of the
  // layer below, bottom up: where a thin piece below was too thin to lay, the piece over it is not
  // laid either, and a line steps out no further than a wall may. Such a layer is planned again (few layers have
  // gap fill; the rest of a layer is as it was).
  const double tan_alpha = std::tan(options.self_supporting_deg * kPi / 180.0);
  for (std::size_t i = 1; options.gap_fill && i < layers.size(); ++i) {
    if (!has_gap_fill(result[i])) continue;
    // Between parallel layers the distance between their planes; tilted layers fan, so the least
    // thickness of this one (as the support check takes them, planner/support.cpp).
    const bool parallel = core::dot(layers[i].frame.d, layers[i - 1].frame.d) >= kParallelCos;
    const double t = parallel ? std::abs(core::dot(layers[i].frame.origin - layers[i - 1].frame.origin, layers[i].frame.d))
                              : layers[i].thickness_range().first;
    const double step = std::max(t * tan_alpha, std::min(options.max_step_mm, 0.5 * options.bead_width_mm));
    const std::vector<geom2d::Polygon> below = beads_under(result[i - 1], layers[i].frame, result[i], options.bead_width_mm, step);
    plan_layer(i, &below);
  }
  for (const std::string& f : failed) {
    if (!f.empty()) return core::make_error(core::ErrorCode::kInfeasible, f);
  }
  return result;
}

}  // namespace

core::Result<std::vector<LayerToolpaths>> make_toolpaths(const mesh::Mesh& mesh, const slicing::SliceResult& slices,
                                                         const ToolpathOptions& options) {
  return core::with_threads(options.threads, [&] { return toolpaths_in_arena(mesh, slices, options); });
}

}  // namespace polyaxis::toolpath
