// Centroidal axis: Ruan, Eiamsa-ard, Liou, "Automatic multi-axis slicing based on centroidal axis
// computation" (2006), §3: sections along one of the six major directions, one centroid per outer
// loop, Eq. 2 between consecutive sections, new branches at Eq. 3–4, FindConnectingLink, break links.
//
// What the paper leaves open, and what this file does:
//  * `inc` ("the smallest distance between two non-intersecting surfaces"): estimated as the
//    smaller of (a) the smallest gap between two feature heights along X, Y or Z, a feature height
//    being the height of a face whose normal lies within kFeatureFaceDeg of that axis (flat tops,
//    bottoms and steps: the surfaces a section sweep must not jump over), gaps under
//    min_increment_mm being tessellation, and (b) the smallest strip width 2A/P of the loops of
//    kThicknessSamples sections along the start direction; then clamped to the options' range.
//  * Eq. 2 per loop, on external contours only (Ruan: "only considering the external boundary";
//    holes filled, so a hollow section drifting sideways still continues): the upper loops are
//    matched to the lower loops (tracks) by overlap. One to one: the pieces of U − (U ∩ L) are
//    checked; a piece is a new branch when its centroid G lies
//    more than kFarFactor·inc from L ("much greater than the distance between the sections").
//    One lower to several upper loops: a split; each upper loop starts a child branch in the same
//    direction, and the branch point is moved down past the sections that still grow outwards
//    going up (the fused root of the arms), whose single centroids describe no arm: they are
//    dropped. Several lower to one upper loop: a merge. When the merging branches are all roots
//    (a part standing on feet), the upper loop starts the root branch and the feet become its
//    children, reversed (direction −D: they hang below the body). Otherwise the merge closes a
//    cycle: the new branch is a child of the first branch, with extra links from the others.
//  * A branch of kShortBranchSections sections or fewer (shorter than 2·inc) cannot spawn a side
//    branch larger than itself: a sliver where a part touches the plate at an edge is not a feature (pen_rack).
//  * Eq. 4: the new branch's first plane lies ε beyond the lower loop's boundary along P; of that
//    section, the loops that contain the piece's points on the line where the two planes meet
//    start the branch (other loops are other geometry). The branch's later sections follow them
//    by overlap; loops that appear unconnected are left to the sweep that owns them.
//  * "B = B − Bs": every section S_i of a sweep, cut at h_i, is kept as the prism
//    [h_i − inc, h_i + inc] × S_i ([h_i, h_i + inc] for a sweep's first section, so a branch never
//    reaches back into its father), so the slab between two sections is covered by both; a
//    branch's prisms are also grown sideways by kCoverGrowFactor·inc (a slanted end face changes
//    the shape between sections). A section of any other sweep is clipped by these prisms: a
//    prism along the same axis contributes its polygon when the plane falls in its range; a
//    prism across contributes the rectangles (its polygon's chords on the line where the planes
//    meet) × its range. Prisms of the sweep itself are not subtracted; loops left smaller than
//    kMinPieceAreaMm2 are clipping residue and dropped.
//  * FindConnectingLink: a child branch links to the father's node nearest its first centroid (the
//    junction node for split children). Breaks: a link whose direction turns from the link ending
//    at its start node by more than break_angle_deg.
#include "polyaxis/analysis/centroidal_axis.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <span>

#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::analysis {
namespace {

using geom2d::Point;
using geom2d::Polygon;
using geom2d::Ring;

// Tolerances of this analysis, with their units.
constexpr double kStartOffsetMm = 1e-3;     // Ruan's ε: first plane above the base, and Eq. 4
constexpr double kFarFactor = 1.5;          // piece centroid farther than this × inc from L: a branch
constexpr std::size_t kShortBranchSections = 2;    // branch of at most this many sections: a short branch (see above)
constexpr double kMinPieceAreaMm2 = 0.01;   // Eq. 2 pieces below this are rounding slivers ...
constexpr double kMinPieceShare = 1e-3;     // ... as are pieces below this share of the upper loop
constexpr double kMinOverlapAreaMm2 = 1e-3; // loops overlapping by less do not continue each other
constexpr double kFeatureFaceDeg = 20.0;    // face normal within this of an axis: a feature height
constexpr double kCoverGrowFactor = 0.5;   // branch bodies grown sideways by this × inc (add_prism)
constexpr int kThicknessSamples = 8;        // sections along the start direction for 2A/P
constexpr double kMaxFeatureCells = 256.0;  // cells along each side of join_features' grid, at most
constexpr int kMaxDepth = 32;               // nesting of branch sweeps; deeper pieces continue
constexpr double kPi = 3.14159265358979323846;

// The six major directions: 0 +X, 1 −X, 2 +Y, 3 −Y, 4 +Z, 5 −Z.
Vec3 major(int k) {
  Vec3 v{};
  v[k / 2] = (k % 2 == 0) ? 1.0 : -1.0;
  return v;
}
int axis_of(int k) { return k / 2; }
int sign_of(int k) { return k % 2 == 0 ? 1 : -1; }
int opposite(int k) { return k ^ 1; }
int closest_major(Vec3 v) {
  int best = 0;
  double best_dot = -INFINITY;
  for (int k = 0; k < 6; ++k) {
    const double d = core::dot(v, major(k));
    if (d > best_dot) best_dot = d, best = k;
  }
  return best;
}

// Frame axes of direction k as signed world axes: plane_frame() gives ± world axes for a major
// direction, and its origin moves along d only, so (u, v) units map to world units exactly.
struct AxisMap {
  int u_axis = 0, v_axis = 1, u_sign = 1, v_sign = 1;
};
AxisMap axis_map(int k) {
  const slicing::Frame f = slicing::plane_frame(major(k), 0.0);
  AxisMap m;
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(f.u[a]) > 0.5) m.u_axis = a, m.u_sign = f.u[a] > 0 ? 1 : -1;
    if (std::fabs(f.v[a]) > 0.5) m.v_axis = a, m.v_sign = f.v[a] > 0 ? 1 : -1;
  }
  return m;
}

// Area and centroid of a polygon (outer minus holes) in units and unit coordinates.
struct Moments {
  double area_mm2 = 0.0;
  double cu = 0.0, cv = 0.0;  // units
};
Moments moments(const Polygon& p) {
  Moments m;
  if (p.outer.empty()) return m;
  const Point ref = p.outer.front();
  double a2 = 0.0, sx = 0.0, sy = 0.0;
  auto ring = [&](const Ring& r) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Point& p0 = r[i];
      const Point& p1 = r[(i + 1) % r.size()];
      const double x0 = static_cast<double>(p0.x - ref.x), y0 = static_cast<double>(p0.y - ref.y);
      const double x1 = static_cast<double>(p1.x - ref.x), y1 = static_cast<double>(p1.y - ref.y);
      const double c = x0 * y1 - x1 * y0;
      a2 += c;
      sx += (x0 + x1) * c;
      sy += (y0 + y1) * c;
    }
  };
  ring(p.outer);
  for (const Ring& h : p.holes) ring(h);
  if (a2 == 0.0) {
    m.cu = static_cast<double>(ref.x);
    m.cv = static_cast<double>(ref.y);
    return m;
  }
  m.area_mm2 = std::fabs(a2) / 2.0 / (geom2d::kUnitsPerMm * geom2d::kUnitsPerMm);
  m.cu = static_cast<double>(ref.x) + sx / (3.0 * a2);
  m.cv = static_cast<double>(ref.y) + sy / (3.0 * a2);
  return m;
}

double perimeter_mm(const Polygon& p) {
  double len = 0.0;
  auto ring = [&](const Ring& r) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Point& a = r[i];
      const Point& b = r[(i + 1) % r.size()];
      len += std::hypot(static_cast<double>(b.x - a.x), static_cast<double>(b.y - a.y));
    }
  };
  ring(p.outer);
  for (const Ring& h : p.holes) ring(h);
  return len / geom2d::kUnitsPerMm;
}

// Distance in mm from point (x, y) (units) to the region of polygon P; 0 inside.
double distance_mm(double x, double y, const Polygon& p) {
  int winding = 0;
  double best = INFINITY;
  auto ring = [&](const Ring& r) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double ax = static_cast<double>(r[i].x), ay = static_cast<double>(r[i].y);
      const double bx = static_cast<double>(r[(i + 1) % r.size()].x), by = static_cast<double>(r[(i + 1) % r.size()].y);
      if ((ay <= y) != (by <= y)) {
        const double xc = ax + (y - ay) * (bx - ax) / (by - ay);
        if (xc > x) winding += by > ay ? 1 : -1;
      }
      const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
      const double t = len2 > 0.0 ? std::clamp(((x - ax) * dx + (y - ay) * dy) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, std::hypot(ax + t * dx - x, ay + t * dy - y));
    }
  };
  ring(p.outer);
  for (const Ring& h : p.holes) ring(h);
  return winding != 0 ? 0.0 : best / geom2d::kUnitsPerMm;
}

struct Box2 {
  std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0;
  std::int64_t x1 = std::numeric_limits<std::int64_t>::min(), y1 = x1;
  void add(const Ring& r) {
    for (const Point& p : r) x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  bool overlaps(const Box2& o) const { return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1; }
};
Box2 box_of(const Polygon& p) {
  Box2 b;
  b.add(p.outer);
  return b;
}

// Intervals (units, along the other coordinate) where the nonzero interior of RINGS meets the
// line {coordinate FIXED (0: x, 1: y) = VALUE}.
using Intervals = std::vector<std::pair<double, double>>;
Intervals intervals_on_line(const std::vector<Ring>& rings, int fixed, double value) {
  std::vector<std::pair<double, int>> hits;
  for (const Ring& r : rings) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Point& a = r[i];
      const Point& b = r[(i + 1) % r.size()];
      const double af = static_cast<double>(fixed == 0 ? a.x : a.y), bf = static_cast<double>(fixed == 0 ? b.x : b.y);
      if ((af < value) == (bf < value)) continue;
      const double ao = static_cast<double>(fixed == 0 ? a.y : a.x), bo = static_cast<double>(fixed == 0 ? b.y : b.x);
      hits.push_back({ao + (value - af) * (bo - ao) / (bf - af), bf > af ? 1 : -1});
    }
  }
  std::sort(hits.begin(), hits.end());
  Intervals out;
  int winding = 0;
  double start = 0.0;
  for (const auto& [at, w] : hits) {
    const int before = winding;
    winding += w;
    if (before == 0 && winding != 0) start = at;
    if (before != 0 && winding == 0 && at > start) out.push_back({start, at});
  }
  return out;
}
bool intervals_overlap(const Intervals& a, const Intervals& b) {
  for (const auto& x : a) {
    for (const auto& y : b) {
      if (x.first < y.second && y.first < x.second) return true;
    }
  }
  return false;
}

double area_of(const std::vector<Polygon>& ps) { return geom2d::area_mm2(ps); }
std::vector<Ring> rings_of(const Polygon& p) { return geom2d::rings_of(std::vector<Polygon>{p}); }

// Sections along one major direction: the context, and faces bucketed by height so a plane at h
// visits only the faces of its bucket (a superset of the crossed faces).
struct Direction {
  int k = 0;
  AxisMap map;
  std::unique_ptr<slicing::SectionContext> context;
  double lo = 0.0, bin_mm = 1.0;
  std::vector<std::uint32_t> offsets, faces;

  std::span<const std::uint32_t> candidates(double h) const {
    if (offsets.size() < 2) return {};
    const double x = (h - lo) / bin_mm;
    if (!(x >= 0.0)) return {};
    const auto b = static_cast<std::size_t>(x);
    if (b + 1 >= offsets.size()) return {};
    return std::span<const std::uint32_t>(faces.data() + offsets[b], offsets[b + 1] - offsets[b]);
  }
};

// One prism of a sweeping body: world axis AXIS in [lo, hi] mm, times a polygon whose points
// are world coordinates (units) of the other two axes in increasing order.
struct Prism {
  int axis = 0;
  double lo = 0.0, hi = 0.0;
  int sweep = 0;
  std::vector<Ring> rings;
  Box2 box;
  std::array<double, 3> min_units{}, max_units{};  // world box, units
};

struct NodeRec {
  Vec3 position;
  double area_mm2 = 0.0;
  std::uint32_t branch = 0;
  bool removed = false;
  Polygon loop;  // the section loop in its direction's frame, units
};

struct BranchRec {
  int k = 4;
  std::optional<std::uint32_t> father;
  std::optional<std::uint32_t> attach;  // father's node the branch links from (else nearest)
  bool reversed = false;
  std::vector<std::uint32_t> nodes;  // in sweep order
};

struct Track {
  std::uint32_t branch = 0;
  std::uint32_t node = 0;
};

// The piece that started a branch: its points on the line where the two planes meet.
struct Seed {
  int line_axis = 0;      // world axis along the line
  int fixed_axis = 0;     // world axis fixed on the line (the father's direction axis)
  double fixed_units = 0; // its value
  Intervals along;        // world units along line_axis
};

// A face whose normal lies within kFeatureFaceDeg of an axis: its heights along the axis and its
// box across it. Joined with others, a feature.
struct Feature {
  double lo, hi;
  double b0, b1, c0, c1;  // box across the axis
};

// Whether the boxes across the axis of X and Y come within NEAR of each other.
bool touches_across(const Feature& x, const Feature& y, double near) {
  return x.b0 <= y.b1 + near && y.b0 <= x.b1 + near && x.c0 <= y.c1 + near && y.c0 <= x.c1 + near;
}

// FACES (sorted by lo) joined into features: faces that overlap in height (within NEAR) and across
// (touches_across), transitively; each feature the union of its faces' spans, in the order of its
// first face. Pairs are looked for only among the faces of one cell of a grid across the axis (a
// face in every cell its box grown by NEAR / 2 meets, so any two that touch share one): faces
// far apart across are never compared, as the flat top and bottom of a ring, each thousands of
// facets at one height, would be pair by pair. Deterministic.
std::vector<Feature> join_features(const std::vector<Feature>& faces, double near) {
  std::vector<std::size_t> parent(faces.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  if (!faces.empty()) {
    double b0 = INFINITY, b1 = -INFINITY, c0 = INFINITY, c1 = -INFINITY;
    for (const Feature& f : faces) b0 = std::min(b0, f.b0), b1 = std::max(b1, f.b1), c0 = std::min(c0, f.c0), c1 = std::max(c1, f.c1);
    const auto side = static_cast<std::int64_t>(std::clamp(std::sqrt(static_cast<double>(faces.size())), 1.0, kMaxFeatureCells));
    const double cell_b = std::max((b1 - b0 + near) / static_cast<double>(side), 1e-9), cell_c = std::max((c1 - c0 + near) / static_cast<double>(side), 1e-9);
    auto cell = [&](double x, double lo, double size) { return std::clamp(static_cast<std::int64_t>(std::floor((x - lo) / size)), std::int64_t{0}, side - 1); };
    std::vector<std::vector<std::size_t>> cells(static_cast<std::size_t>(side * side));
    for (std::size_t i = 0; i < faces.size(); ++i) {  // in order: each cell's faces sorted by lo
      const Feature& f = faces[i];
      const std::int64_t i0 = cell(f.b0 - near / 2, b0 - near / 2, cell_b), i1 = cell(f.b1 + near / 2, b0 - near / 2, cell_b);
      const std::int64_t j0 = cell(f.c0 - near / 2, c0 - near / 2, cell_c), j1 = cell(f.c1 + near / 2, c0 - near / 2, cell_c);
      for (std::int64_t u = i0; u <= i1; ++u) {
        for (std::int64_t v = j0; v <= j1; ++v) cells[static_cast<std::size_t>(u * side + v)].push_back(i);
      }
    }
    for (const std::vector<std::size_t>& in : cells) {
      for (std::size_t x = 0; x < in.size(); ++x) {
        for (std::size_t y = x + 1; y < in.size() && faces[in[y]].lo < faces[in[x]].hi + near; ++y) {
          if (touches_across(faces[in[x]], faces[in[y]], near)) parent[find(in[y])] = find(in[x]);
        }
      }
    }
  }
  std::vector<Feature> features;
  std::vector<std::size_t> slot(faces.size(), SIZE_MAX);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const std::size_t r = find(i);
    if (slot[r] == SIZE_MAX) {
      slot[r] = features.size();
      features.push_back(faces[i]);
      continue;
    }
    Feature& g = features[slot[r]];
    const Feature& f = faces[i];
    g.lo = std::min(g.lo, f.lo), g.hi = std::max(g.hi, f.hi);
    g.b0 = std::min(g.b0, f.b0), g.b1 = std::max(g.b1, f.b1), g.c0 = std::min(g.c0, f.c0), g.c1 = std::max(g.c1, f.c1);
  }
  return features;
}

// The least gap along axis A (0, 1, 2) of at least NEAR between two features of M that face each
// other across it (their boxes touch across); infinite when there is none.
double feature_gap(const mesh::Mesh& m, int a, double near) {
  const int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
  const double feature_cos = std::cos(kFeatureFaceDeg * kPi / 180.0);
  std::vector<Feature> faces;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const Vec3 n = core::normalized(mesh::face_area_vector(m, f));
    if (std::fabs(n[a]) < feature_cos) continue;
    const Vec3 p0 = m.corner(f, 0), p1 = m.corner(f, 1), p2 = m.corner(f, 2);
    faces.push_back({std::min({p0[a], p1[a], p2[a]}), std::max({p0[a], p1[a], p2[a]}), std::min({p0[b], p1[b], p2[b]}),
                     std::max({p0[b], p1[b], p2[b]}), std::min({p0[c], p1[c], p2[c]}), std::max({p0[c], p1[c], p2[c]})});
  }
  std::sort(faces.begin(), faces.end(), [](const Feature& x, const Feature& y) { return x.lo < y.lo; });
  const std::vector<Feature> features = join_features(faces, near);
  double gap = INFINITY;
  for (const Feature& x : features) {
    for (const Feature& y : features) {
      const double g = y.lo - x.hi;
      if (g >= near && g < gap && touches_across(x, y, near)) gap = g;
    }
  }
  return gap;
}

class Engine {
 public:
  Engine(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology, const CentroidalAxisOptions& options)
      : mesh_(mesh), topology_(topology), options_(options) {}

  core::Result<CentroidalAxis> run(int start_k);

 private:
  double estimate_increment(int start_k);
  Direction& direction(int k);
  std::vector<Polygon> cut(int k, double h, int sweep);
  std::vector<Ring> covered(int k, double h, int sweep, std::size_t first_prism, const Box2& near) const;
  void add_prism(int k, double h, const Polygon& loop, int sweep, bool has_previous);
  std::uint32_t new_branch(int k, std::optional<std::uint32_t> father);
  std::uint32_t add_node(std::uint32_t branch, int k, double h, Polygon loop);
  void sweep(int k, double h0, int depth, std::optional<std::uint32_t> father, const Seed* seed);
  bool seed_matches(const Seed& seed, int k, const Polygon& loop) const;
  std::uint32_t junction_node(std::uint32_t branch);
  Vec3 to_world(int k, double h, double u_units, double v_units) const;
  CentroidalAxis finish() const;

  const mesh::Mesh& mesh_;
  const mesh::EdgeTopology& topology_;
  const CentroidalAxisOptions& options_;
  core::Progress progress_{"axis nodes", 0};  // the count of nodes found so far
  double inc_ = 1.0;
  std::array<std::unique_ptr<Direction>, 6> directions_;
  slicing::SectionScratch scratch_;
  std::vector<Prism> prisms_;
  std::vector<NodeRec> nodes_;
  std::vector<BranchRec> branches_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> extra_links_;
  int sweeps_ = 0;
};

Direction& Engine::direction(int k) {
  if (directions_[k]) return *directions_[k];
  auto d = std::make_unique<Direction>();
  d->k = k;
  d->map = axis_map(k);
  d->context = std::make_unique<slicing::SectionContext>(mesh_, major(k), &topology_);
  const slicing::SectionContext& c = *d->context;
  d->lo = c.min_height();
  d->bin_mm = inc_;
  const auto bins = static_cast<std::size_t>(std::floor((c.max_height() - c.min_height()) / inc_)) + 1;
  d->offsets.assign(bins + 1, 0);
  auto bin_of = [&](double h) {
    return std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, std::floor((h - d->lo) / inc_))));
  };
  const auto n = static_cast<std::uint32_t>(mesh_.triangles.size());
  for (std::uint32_t f = 0; f < n; ++f) {
    for (std::size_t b = bin_of(c.face_min(f)), e = bin_of(c.face_max(f)); b <= e; ++b) ++d->offsets[b + 1];
  }
  std::partial_sum(d->offsets.begin(), d->offsets.end(), d->offsets.begin());
  d->faces.resize(d->offsets.back());
  std::vector<std::uint32_t> fill(d->offsets.begin(), d->offsets.end() - 1);
  for (std::uint32_t f = 0; f < n; ++f) {
    for (std::size_t b = bin_of(c.face_min(f)), e = bin_of(c.face_max(f)); b <= e; ++b) d->faces[fill[b]++] = f;
  }
  directions_[k] = std::move(d);
  return *directions_[k];
}

Vec3 Engine::to_world(int k, double h, double u_units, double v_units) const {
  const slicing::Frame f = slicing::plane_frame(major(k), h);
  return f.to_world(u_units / geom2d::kUnitsPerMm, v_units / geom2d::kUnitsPerMm);
}

double Engine::estimate_increment(int start_k) {
  // (a) gaps between feature heights along each axis: each feature face spans an interval of
  // heights; overlapping intervals (or closer than min_increment_mm) are one feature, with the
  // box of its faces across the axis. Two features are a gap only where those boxes overlap:
  // surfaces that do not face each other are not "two surfaces" of Ruan's definition.
  double gap = INFINITY;
  for (int a = 0; a < 3; ++a) gap = std::min(gap, feature_gap(mesh_, a, options_.min_increment_mm));
  // (b) the thinnest strip among sections along the start direction.
  double strip = INFINITY;
  const slicing::SectionContext context(mesh_, major(start_k), &topology_);
  const double lo = context.min_height(), hi = context.max_height();
  std::vector<std::uint32_t> candidates;
  for (int i = 0; i < kThicknessSamples; ++i) {
    const double h = lo + (hi - lo) * (i + 0.5) / kThicknessSamples;
    candidates.clear();
    for (std::uint32_t f = 0; f < mesh_.triangles.size(); ++f) {
      if (context.face_min(f) <= h && context.face_max(f) >= h) candidates.push_back(f);
    }
    const auto s = slicing::section(context, h, slicing::plane_frame(major(start_k), h), candidates, scratch_);
    for (const Polygon& p : s.polygons) {
      const double per = perimeter_mm(p);
      if (per > 0.0) strip = std::min(strip, 2.0 * geom2d::area_mm2(p) / per);
    }
  }
  const double estimate = std::min(gap, strip);
  if (!std::isfinite(estimate)) return options_.max_increment_mm;
  return std::clamp(estimate, options_.min_increment_mm, options_.max_increment_mm);
}

// Rings (in direction K's frame at H) of the prisms of other sweeps than SWEEP, from FIRST_PRISM.
// Only prisms whose world box meets NEAR (a box in the frame) are looked at.
std::vector<Ring> Engine::covered(int k, double h, int sweep, std::size_t first_prism, const Box2& near) const {
  std::vector<Ring> out;
  const AxisMap m = axis_map(k);
  auto world_range = [](std::int64_t a, std::int64_t b, int sign) {
    return sign > 0 ? std::pair{static_cast<double>(a), static_cast<double>(b)} : std::pair{-static_cast<double>(b), -static_cast<double>(a)};
  };
  const auto [nu0, nu1] = world_range(near.x0, near.x1, m.u_sign);
  const auto [nv0, nv1] = world_range(near.y0, near.y1, m.v_sign);
  const int plane_axis = axis_of(k);
  const double w_mm = sign_of(k) * h;
  const double w_units = w_mm * geom2d::kUnitsPerMm;
  // World (axis -> units) to frame point.
  auto to_frame = [&](const std::array<std::int64_t, 3>& world) {
    return Point{m.u_sign * world[m.u_axis], m.v_sign * world[m.v_axis]};
  };
  for (std::size_t i = first_prism; i < prisms_.size(); ++i) {
    const Prism& p = prisms_[i];
    if (p.sweep == sweep) continue;
    if (p.max_units[m.u_axis] < nu0 || p.min_units[m.u_axis] > nu1 || p.max_units[m.v_axis] < nv0 ||
        p.min_units[m.v_axis] > nv1) {
      continue;
    }
    const int b = p.axis == 0 ? 1 : 0, c = p.axis == 2 ? 1 : 2;  // the prism polygon's axes (x, y)
    if (p.axis == plane_axis) {
      if (w_mm < p.lo || w_mm > p.hi) continue;
      for (const Ring& r : p.rings) {
        Ring q;
        q.reserve(r.size());
        for (const Point& pt : r) {
          std::array<std::int64_t, 3> world{};
          world[b] = pt.x;
          world[c] = pt.y;
          q.push_back(to_frame(world));
        }
        out.push_back(std::move(q));
      }
      continue;
    }
    const int fixed = plane_axis == b ? 0 : 1;  // which polygon coordinate the plane fixes
    const int along = fixed == 0 ? c : b;       // world axis along the chords
    if (fixed == 0 ? (w_units < static_cast<double>(p.box.x0) || w_units > static_cast<double>(p.box.x1))
                   : (w_units < static_cast<double>(p.box.y0) || w_units > static_cast<double>(p.box.y1))) {
      continue;
    }
    const auto lo_u = geom2d::to_units(p.lo), hi_u = geom2d::to_units(p.hi);
    for (const auto& [e0, e1] : intervals_on_line(p.rings, fixed, w_units)) {
      const auto a0 = static_cast<std::int64_t>(std::floor(e0)), a1 = static_cast<std::int64_t>(std::ceil(e1));
      Ring q;
      for (const auto& [s, t] : {std::pair{lo_u, a0}, std::pair{hi_u, a0}, std::pair{hi_u, a1}, std::pair{lo_u, a1}}) {
        std::array<std::int64_t, 3> world{};
        world[p.axis] = s;
        world[along] = t;
        q.push_back(to_frame(world));
      }
      out.push_back(std::move(q));
    }
  }
  return out;
}

std::vector<Polygon> Engine::cut(int k, double h, int sweep) {
  Direction& d = direction(k);
  auto s = slicing::section(*d.context, h, slicing::plane_frame(major(k), h), d.candidates(h), scratch_);
  if (s.polygons.empty()) return {};
  Box2 near;
  for (const Polygon& p : s.polygons) near.add(p.outer);
  const std::vector<Ring> cover = covered(k, h, sweep, 0, near);
  std::vector<Polygon> out =
      cover.empty() ? std::move(s.polygons) : geom2d::difference_rings(geom2d::rings_of(s.polygons), cover);
  // Residue of clipping (slivers along the sweeping bodies' faces) is not a loop.
  std::erase_if(out, [](const Polygon& p) { return geom2d::area_mm2(p) <= kMinPieceAreaMm2; });
  return out;
}

void Engine::add_prism(int k, double h, const Polygon& loop, int sweep, bool has_previous) {
  // A section covers the slab above it, and the slab below it when the track had a section
  // there: the slab between two sections is then covered by the union of both, which holds a
  // section that drifts between them by less than its own width.
  Prism p;
  p.axis = axis_of(k);
  const double below = has_previous ? h - inc_ : h;
  p.lo = sign_of(k) > 0 ? below : -(h + inc_);
  p.hi = sign_of(k) > 0 ? h + inc_ : -below;
  p.sweep = sweep;
  const AxisMap m = axis_map(k);
  const int b = p.axis == 0 ? 1 : 0;
  // A branch's body is grown sideways by kCoverGrowFactor·inc: between sections a branch's
  // shape also changes (an end face slanted to the sweep), and what the sections miss there
  // would come back as stray loops in the sweeps along other directions. The root's body is
  // kept exact: its branches start beyond it along their own direction.
  std::vector<Polygon> grown{loop};
  if (sweep != 0) grown = geom2d::offset(grown, kCoverGrowFactor * inc_);
  for (const Ring& r : geom2d::rings_of(grown)) {
    Ring q;
    q.reserve(r.size());
    for (const Point& pt : r) {
      std::array<std::int64_t, 3> world{};
      world[m.u_axis] = m.u_sign * pt.x;
      world[m.v_axis] = m.v_sign * pt.y;
      const int c = p.axis == 2 ? 1 : 2;
      q.push_back({world[b], world[c]});
    }
    p.box.add(q);
    p.rings.push_back(std::move(q));
  }
  p.min_units[p.axis] = p.lo * geom2d::kUnitsPerMm;
  p.max_units[p.axis] = p.hi * geom2d::kUnitsPerMm;
  p.min_units[b] = static_cast<double>(p.box.x0), p.max_units[b] = static_cast<double>(p.box.x1);
  const int c = p.axis == 2 ? 1 : 2;
  p.min_units[c] = static_cast<double>(p.box.y0), p.max_units[c] = static_cast<double>(p.box.y1);
  prisms_.push_back(std::move(p));
}

std::uint32_t Engine::new_branch(int k, std::optional<std::uint32_t> father) {
  BranchRec b;
  b.k = k;
  b.father = father;
  branches_.push_back(std::move(b));
  return static_cast<std::uint32_t>(branches_.size() - 1);
}

std::uint32_t Engine::add_node(std::uint32_t branch, int k, double h, Polygon loop) {
  const Moments mo = moments(loop);
  NodeRec n;
  n.position = to_world(k, h, mo.cu, mo.cv);
  n.area_mm2 = mo.area_mm2;
  n.branch = branch;
  n.loop = std::move(loop);
  nodes_.push_back(std::move(n));
  progress_.update(nodes_.size());
  const auto id = static_cast<std::uint32_t>(nodes_.size() - 1);
  branches_[branch].nodes.push_back(id);
  return id;
}

bool Engine::seed_matches(const Seed& seed, int k, const Polygon& loop) const {
  const AxisMap m = axis_map(k);
  // The seed's line in this frame: the fixed world axis is u or v here.
  const int fixed = m.u_axis == seed.fixed_axis ? 0 : 1;
  const int fsign = fixed == 0 ? m.u_sign : m.v_sign;
  const int osign = fixed == 0 ? m.v_sign : m.u_sign;
  Intervals mine = intervals_on_line(rings_of(loop), fixed, fsign * seed.fixed_units);
  for (auto& [a, b] : mine) {
    a *= osign;
    b *= osign;
    if (a > b) std::swap(a, b);
  }
  return intervals_overlap(mine, seed.along);
}

// The branch point of a split: walking down BRANCH from its last node while each section still
// sticks out of the one below (the fused roots of the arms); those nodes are dropped.
std::uint32_t Engine::junction_node(std::uint32_t branch) {
  auto& ids = branches_[branch].nodes;
  std::size_t j = ids.size() - 1;
  while (j > 0) {
    const Polygon& up = nodes_[ids[j]].loop;
    const Polygon& down = nodes_[ids[j - 1]].loop;
    const double grown = area_of(geom2d::difference_rings({up.outer}, {down.outer}));
    if (grown <= std::max(kMinPieceAreaMm2, kMinPieceShare * nodes_[ids[j]].area_mm2)) break;
    --j;
  }
  for (std::size_t i = j + 1; i < ids.size(); ++i) nodes_[ids[i]].removed = true;
  return ids[j];
}

void Engine::sweep(int k, double h0, int depth, std::optional<std::uint32_t> father, const Seed* seed) {
  const int sweep_id = sweeps_++;
  const bool root_sweep = seed == nullptr;
  const double top = direction(k).context->max_height();
  std::vector<Track> tracks;
  for (Polygon& loop : cut(k, h0, sweep_id)) {
    if (seed && !seed_matches(*seed, k, loop)) continue;
    const std::uint32_t b = new_branch(k, father);
    add_prism(k, h0, loop, sweep_id, false);
    tracks.push_back({b, add_node(b, k, h0, std::move(loop))});
  }
  const AxisMap map = axis_map(k);
  for (double h = h0; !tracks.empty(); h += inc_) {
    const double h1 = h + inc_;
    if (h1 >= top) break;
    std::vector<Polygon> uppers = cut(k, h1, sweep_id);
    const std::size_t prisms_at_cut = prisms_.size();
    // Overlap graph between lower loops (tracks) and upper loops.
    const std::size_t nt = tracks.size(), nu = uppers.size();
    std::vector<Box2> ubox(nu);
    std::vector<double> uarea(nu);
    for (std::size_t j = 0; j < nu; ++j) ubox[j] = box_of(uppers[j]), uarea[j] = std::fabs(geom2d::signed_area_mm2(uppers[j].outer));
    std::vector<std::vector<std::size_t>> t_up(nt), u_low(nu);
    std::vector<std::vector<Polygon>> outside_of(nt * nu);  // U_j − L_i, reused as Eq. 2's pieces
    for (std::size_t i = 0; i < nt; ++i) {
      const Polygon& low = nodes_[tracks[i].node].loop;
      const Box2 lb = box_of(low);
      for (std::size_t j = 0; j < nu; ++j) {
        if (!lb.overlaps(ubox[j])) continue;
        std::vector<Polygon>& outside = outside_of[i * nu + j];
        outside = geom2d::difference_rings({uppers[j].outer}, {low.outer});
        if (uarea[j] - area_of(outside) > kMinOverlapAreaMm2) t_up[i].push_back(j), u_low[j].push_back(i);
      }
    }
    // Connected components of the bipartite graph, by tracks then uppers.
    std::vector<int> t_comp(nt, -1), u_comp(nu, -1);
    int comps = 0;
    for (std::size_t i = 0; i < nt; ++i) {
      if (t_comp[i] >= 0 || t_up[i].empty()) continue;
      std::vector<std::pair<bool, std::size_t>> stack{{true, i}};
      t_comp[i] = comps;
      while (!stack.empty()) {
        auto [is_t, x] = stack.back();
        stack.pop_back();
        for (std::size_t y : is_t ? t_up[x] : u_low[x]) {
          int& c = is_t ? u_comp[y] : t_comp[y];
          if (c < 0) c = comps, stack.push_back({!is_t, y});
        }
      }
      ++comps;
    }
    std::vector<Track> next;
    // Uppers still to be clipped by prisms added since the cut (child sweeps of this step).
    auto refresh = [&](Polygon& u, const Polygon* prefer) -> bool {
      if (prisms_.size() == prisms_at_cut) return true;
      const std::vector<Ring> cover = covered(k, h1, sweep_id, prisms_at_cut, box_of(u));
      if (cover.empty()) return true;
      std::vector<Polygon> left = geom2d::difference_rings(rings_of(u), cover);
      if (left.empty()) return false;
      std::size_t best = 0;
      double best_score = -INFINITY;
      for (std::size_t q = 0; q < left.size(); ++q) {
        double score = geom2d::area_mm2(left[q]);
        if (prefer) score -= area_of(geom2d::difference_rings(rings_of(left[q]), rings_of(*prefer)));
        if (score > best_score) best_score = score, best = q;
      }
      if (geom2d::area_mm2(left[best]) <= kMinOverlapAreaMm2) return false;
      u = std::move(left[best]);
      return true;
    };
    for (int c = 0; c < comps; ++c) {
      std::vector<std::size_t> ts, us;
      for (std::size_t i = 0; i < nt; ++i) if (t_comp[i] == c) ts.push_back(i);
      for (std::size_t j = 0; j < nu; ++j) if (u_comp[j] == c) us.push_back(j);
      if (ts.size() == 1 && us.size() == 1) {
        // Eq. 2 on one lower and one upper loop.
        const Track tr = tracks[ts[0]];
        const Polygon lower = nodes_[tr.node].loop;
        const double lower_area = std::fabs(geom2d::signed_area_mm2(lower.outer));
        const Vec3 c_lower = nodes_[tr.node].position;
        Polygon upper = uppers[us[0]];
        const std::vector<Polygon> pieces = std::move(outside_of[ts[0] * nu + us[0]]);
        for (const Polygon& piece : pieces) {
          const Moments g = moments(piece);
          // Only far pieces matter here, and rounding never makes a far piece: the absolute floor
          // alone (a sliver where a round-bottomed feature first shows is a real piece).
          if (g.area_mm2 <= kMinPieceAreaMm2 || depth >= kMaxDepth) continue;
          if (distance_mm(g.cu, g.cv, Polygon{lower.outer, {}}) <= kFarFactor * inc_) continue;
          const bool short_branch = branches_[tr.branch].nodes.size() <= kShortBranchSections && g.area_mm2 > lower_area;
          if (short_branch) continue;
          const int kp = closest_major(to_world(k, h1, g.cu, g.cv) - c_lower);
          if (axis_of(kp) == axis_of(k)) continue;
          // Eq. 4: T = max of ∂Lower projected on P; the new plane is ε beyond it.
          const bool p_is_u = map.u_axis == axis_of(kp);
          const int p_sign = (p_is_u ? map.u_sign : map.v_sign) * sign_of(kp);
          double t_units = -INFINITY;
          for (const Point& pt : lower.outer) t_units = std::max(t_units, p_sign * static_cast<double>(p_is_u ? pt.x : pt.y));
          const double h_new = t_units / geom2d::kUnitsPerMm + kStartOffsetMm;
          // The piece's chords on the line where the planes meet, as world intervals.
          Seed s;
          s.fixed_axis = axis_of(k);
          s.fixed_units = sign_of(k) * h1 * geom2d::kUnitsPerMm;
          s.line_axis = p_is_u ? map.v_axis : map.u_axis;
          const int line_sign = p_is_u ? map.v_sign : map.u_sign;
          s.along = intervals_on_line(rings_of(piece), p_is_u ? 0 : 1, p_sign * h_new * geom2d::kUnitsPerMm);
          for (auto& [a, b] : s.along) {
            a *= line_sign;
            b *= line_sign;
            if (a > b) std::swap(a, b);
          }
          if (s.along.empty()) continue;
          sweep(kp, h_new, depth + 1, tr.branch, &s);
        }
        if (!refresh(upper, &lower)) continue;
        add_prism(k, h1, upper, sweep_id, true);
        next.push_back({tr.branch, add_node(tr.branch, k, h1, std::move(upper))});
      } else if (ts.size() == 1) {
        // A split: each upper loop a child branch from the junction node.
        const Track tr = tracks[ts[0]];
        const std::uint32_t j = junction_node(tr.branch);
        for (std::size_t u : us) {
          Polygon upper = uppers[u];
          if (!refresh(upper, nullptr)) continue;
          const std::uint32_t b = new_branch(k, tr.branch);
          branches_[b].attach = j;
          add_prism(k, h1, upper, sweep_id, true);
          next.push_back({b, add_node(b, k, h1, std::move(upper))});
        }
      } else {
        // A merge (several lower loops into one or more upper loops).
        bool all_roots = us.size() == 1;
        for (std::size_t i : ts) all_roots = all_roots && !branches_[tracks[i].branch].father;
        const std::uint32_t first = tracks[ts[0]].branch;
        for (std::size_t u : us) {
          Polygon upper = uppers[u];
          if (!refresh(upper, nullptr)) continue;
          const std::uint32_t b = new_branch(k, all_roots ? std::nullopt : std::optional<std::uint32_t>(first));
          add_prism(k, h1, upper, sweep_id, true);
          const std::uint32_t node = add_node(b, k, h1, std::move(upper));
          if (all_roots) {
            for (std::size_t i : ts) {
              BranchRec& foot = branches_[tracks[i].branch];
              foot.father = b;
              foot.reversed = true;
              foot.k = opposite(foot.k);
            }
          } else {
            branches_[b].attach = tracks[ts[0]].node;
            for (std::size_t q = 1; q < ts.size(); ++q) extra_links_.push_back({tracks[ts[q]].node, node});
          }
          next.push_back({b, node});
        }
      }
    }
    // Loops touching no lower loop: in the root sweep, new roots (geometry hanging from above).
    if (root_sweep) {
      for (std::size_t j = 0; j < nu; ++j) {
        if (!u_low[j].empty()) continue;
        Polygon upper = uppers[j];
        if (!refresh(upper, nullptr)) continue;
        const std::uint32_t b = new_branch(k, std::nullopt);
        add_prism(k, h1, upper, sweep_id, true);
        next.push_back({b, add_node(b, k, h1, std::move(upper))});
      }
    }
    tracks = std::move(next);
  }
}

CentroidalAxis Engine::finish() const {
  CentroidalAxis out;
  out.increment_mm = inc_;
  // Node order of a branch in growth order, without dropped nodes.
  auto growth = [&](const BranchRec& b) {
    std::vector<std::uint32_t> ids;
    for (std::uint32_t n : b.nodes) if (!nodes_[n].removed) ids.push_back(n);
    if (b.reversed) std::reverse(ids.begin(), ids.end());
    return ids;
  };
  // Effective father: skip branches left without nodes.
  const std::size_t nb = branches_.size();
  std::vector<char> empty(nb);
  for (std::size_t b = 0; b < nb; ++b) empty[b] = growth(branches_[b]).empty();
  auto father_of = [&](std::size_t b) -> std::optional<std::uint32_t> {
    std::optional<std::uint32_t> f = branches_[b].father;
    while (f && empty[*f]) f = branches_[*f].father;
    return f;
  };
  // Branch order: depth first from the roots, children in creation order.
  std::vector<std::vector<std::uint32_t>> kids(nb);
  std::vector<std::uint32_t> roots;
  for (std::uint32_t b = 0; b < nb; ++b) {
    if (empty[b]) continue;
    if (auto f = father_of(b)) kids[*f].push_back(b);
    else roots.push_back(b);
  }
  std::vector<std::uint32_t> order, new_id(nb, 0);
  std::vector<std::uint32_t> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const std::uint32_t b = stack.back();
    stack.pop_back();
    new_id[b] = static_cast<std::uint32_t>(order.size());
    order.push_back(b);
    for (auto it = kids[b].rbegin(); it != kids[b].rend(); ++it) stack.push_back(*it);
  }
  // Nodes.
  std::vector<std::uint32_t> node_id(nodes_.size(), 0);
  for (std::uint32_t b : order) {
    AxisBranch ab;
    ab.id = new_id[b];
    ab.direction = major(branches_[b].k);
    if (auto f = father_of(b)) ab.father = new_id[*f];
    for (std::uint32_t n : growth(branches_[b])) {
      AxisNode an;
      an.id = static_cast<std::uint32_t>(out.nodes.size());
      an.position = nodes_[n].position;
      an.direction = ab.direction;
      an.area_mm2 = nodes_[n].area_mm2;
      an.branch = ab.id;
      node_id[n] = an.id;
      ab.nodes.push_back(an.id);
      out.nodes.push_back(an);
    }
    out.branches.push_back(std::move(ab));
  }
  for (std::uint32_t b : order) {
    AxisBranch& ab = out.branches[new_id[b]];
    for (std::uint32_t c : kids[b]) ab.children.push_back(new_id[c]);
    for (std::uint32_t c : ab.children) {
      for (std::uint32_t s : ab.children) if (s != c) out.branches[c].brothers.push_back(s);
    }
  }
  // Links: FindConnectingLink, then the branch's own chain.
  for (std::uint32_t b : order) {
    const AxisBranch& ab = out.branches[new_id[b]];
    if (ab.father) {
      const AxisBranch& fb = out.branches[*ab.father];
      std::optional<std::uint32_t> attach;
      const auto& rec = branches_[b];
      if (rec.attach && !nodes_[*rec.attach].removed && father_of(b) == rec.father) attach = node_id[*rec.attach];
      if (!attach) {
        const Vec3 first = out.nodes[ab.nodes.front()].position;
        double best = INFINITY;
        for (std::uint32_t n : fb.nodes) {
          const double d = core::norm(out.nodes[n].position - first);
          if (d < best) best = d, attach = n;
        }
      }
      if (attach) out.links.push_back({*attach, ab.nodes.front(), false});
    }
    for (std::size_t i = 1; i < ab.nodes.size(); ++i) out.links.push_back({ab.nodes[i - 1], ab.nodes[i], false});
  }
  for (const auto& [from, to] : extra_links_) {
    if (nodes_[from].removed || nodes_[to].removed) continue;
    out.links.push_back({node_id[from], node_id[to], false});
  }
  // C¹ breaks: the turn from the (first) link ending at the start node.
  std::vector<std::optional<std::size_t>> incoming(out.nodes.size());
  for (std::size_t i = 0; i < out.links.size(); ++i) {
    if (!incoming[out.links[i].to]) incoming[out.links[i].to] = i;
  }
  const double cos_break = std::cos(options_.break_angle_deg * kPi / 180.0);
  for (AxisLink& l : out.links) {
    const auto& in = incoming[l.from];
    if (!in) continue;
    const AxisLink& p = out.links[*in];
    const Vec3 a = core::normalized(out.nodes[p.to].position - out.nodes[p.from].position);
    const Vec3 b = core::normalized(out.nodes[l.to].position - out.nodes[l.from].position);
    if (core::norm(a) > 0.0 && core::norm(b) > 0.0 && core::dot(a, b) < cos_break) l.is_break = true;
  }
  return out;
}

core::Result<CentroidalAxis> Engine::run(int start_k) {
  inc_ = estimate_increment(start_k);
  const Direction& d = direction(start_k);
  sweep(start_k, d.context->min_height() + kStartOffsetMm, 0, std::nullopt, nullptr);
  return finish();
}

}  // namespace

core::Result<CentroidalAxis> centroidal_axis(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology,
                                             const CentroidalAxisOptions& options) {
  if (!(options.min_increment_mm > 0.0) || !(options.max_increment_mm >= options.min_increment_mm) ||
      !std::isfinite(options.max_increment_mm)) {
    return core::make_error(core::ErrorCode::kUsage,
                            fmt::format("centroidal axis: increment range [{}, {}] mm is not a positive interval",
                                        options.min_increment_mm, options.max_increment_mm));
  }
  if (!(options.break_angle_deg > 0.0 && options.break_angle_deg < 180.0)) {
    return core::make_error(core::ErrorCode::kUsage,
                            fmt::format("centroidal axis: break angle {} deg is not in (0, 180)", options.break_angle_deg));
  }
  const Vec3 s = core::normalized(options.start_direction);
  const int start_k = closest_major(s);
  if (!core::is_finite(s) || core::dot(s, major(start_k)) < 1.0 - 1e-9) {
    return core::make_error(core::ErrorCode::kUsage,
                            fmt::format("centroidal axis: start direction ({}, {}, {}) is not one of ±X, ±Y, ±Z",
                                        options.start_direction.x, options.start_direction.y, options.start_direction.z));
  }
  if (mesh.triangles.empty()) {
    return core::make_error(core::ErrorCode::kInvalidInput, "centroidal axis: the mesh has no faces");
  }
  if (topology.opposite.size() != 3 * mesh.triangles.size() || !topology.closed()) {
    return core::make_error(core::ErrorCode::kInvalidInput,
                            fmt::format("centroidal axis: the mesh is not closed ({} boundary, {} non-manifold edges)",
                                        topology.boundary_edges, topology.nonmanifold_edges));
  }
  Engine engine(mesh, topology, options);
  return engine.run(start_k);
}

Vec3 nearest_major_direction(Vec3 d) {
  const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  if (az >= ax && az >= ay) return {0, 0, d.z < 0 ? -1.0 : 1.0};
  if (ay >= ax) return {0, d.y < 0 ? -1.0 : 1.0, 0};
  return {d.x < 0 ? -1.0 : 1.0, 0, 0};
}

}  // namespace polyaxis::analysis
