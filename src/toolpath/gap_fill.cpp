// Centre lines of thin pieces through CGAL's straight skeleton. The only translation unit of the
// toolpath module that includes CGAL.
#include "gap_fill.h"

#include "polyaxis/geom2d/clip.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/create_straight_skeleton_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace polyaxis::toolpath::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// A run of centre line shorter than this many bead widths would lay a blob, not a bead: dropped.
constexpr double kMinRunBeads = 0.25;
// The piece's outline is simplified to within this (mm) before its skeleton is taken: a finely
// tessellated arc loses its many short sides (the skeleton's cost grows with their square) and the
// line moves by no more than this, far below a bead.
constexpr double kSimplifyMm = 0.01;
// A piece still of more sides than this is left to the caller (reported, not laid): the skeleton
// would cost about a second a piece.
constexpr std::size_t kMaxSides = 600;

// A point of the centre line: (u, v) mm from the piece's first vertex, and the piece's half
// width there (the skeleton's distance to the boundary).
struct Node {
  double x = 0.0, y = 0.0, r = 0.0;
};

struct Edge {
  std::size_t to = 0;
  double length = 0.0;
};

double distance(const Node& a, const Node& b) { return std::hypot(b.x - a.x, b.y - a.y); }

Node between(const Node& a, const Node& b, double t) { return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.r + (b.r - a.r) * t}; }

// The nodes and inner edges of the straight skeleton of the simple polygon POINTS (mm); empty
// when CGAL cannot build it.
// (GCC 12 sees CGAL's is_simple_2 read a local it has not set, where it has: a false report.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
bool skeleton(const std::vector<Kernel::Point_2>& points, std::vector<Node>& nodes, std::vector<std::vector<Edge>>& edges) {
  CGAL::Polygon_2<Kernel> polygon(points.begin(), points.end());
  if (!polygon.is_simple()) return false;
  if (polygon.is_clockwise_oriented()) polygon.reverse_orientation();
  try {
    const auto ss = CGAL::create_interior_straight_skeleton_2(polygon.vertices_begin(), polygon.vertices_end(), Kernel());
    if (!ss) return false;
    std::map<int, std::size_t> index;  // skeleton vertex id -> node
    auto node_of = [&](const auto& v) {
      const auto [it, added] = index.try_emplace(v->id(), nodes.size());
      if (added) nodes.push_back({CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()), CGAL::to_double(v->time())});
      return it->second;
    };
    for (auto h = ss->halfedges_begin(); h != ss->halfedges_end(); ++h) {
      if (!h->is_inner_bisector() || h->id() > h->opposite()->id()) continue;
      const std::size_t a = node_of(h->opposite()->vertex()), b = node_of(h->vertex());
      if (edges.size() < nodes.size()) edges.resize(nodes.size());
      const double length = distance(nodes[a], nodes[b]);
      edges[a].push_back({b, length});
      edges[b].push_back({a, length});
    }
  } catch (...) {  // CGAL's precondition failures on degenerate input: no line
    return false;
  }
  edges.resize(nodes.size());
  return !nodes.empty();
}
#pragma GCC diagnostic pop

// The node farthest from START along the tree, with each node's parent on the way.
std::size_t farthest(const std::vector<std::vector<Edge>>& edges, std::size_t start, std::vector<std::size_t>& parent) {
  std::vector<double> dist(edges.size(), -1.0);
  parent.assign(edges.size(), SIZE_MAX);
  std::vector<std::size_t> stack{start};
  dist[start] = 0.0;
  std::size_t best = start;
  while (!stack.empty()) {
    const std::size_t n = stack.back();
    stack.pop_back();
    if (dist[n] > dist[best]) best = n;
    for (const Edge& e : edges[n]) {
      if (dist[e.to] >= 0.0) continue;
      dist[e.to] = dist[n] + e.length;
      parent[e.to] = n;
      stack.push_back(e.to);
    }
  }
  return best;
}

// The parts of PATH where the half width is at least HALF_MIN, cut where it crosses that.
std::vector<std::vector<Node>> wide_runs(const std::vector<Node>& path, double half_min) {
  std::vector<std::vector<Node>> runs;
  std::vector<Node> run;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const bool in = path[i].r >= half_min;
    if (i > 0 && in != (path[i - 1].r >= half_min)) {
      const Node& a = path[i - 1];
      run.push_back(between(a, path[i], (half_min - a.r) / (path[i].r - a.r)));
      if (!in) runs.push_back(std::move(run)), run.clear();
    }
    if (in) run.push_back(path[i]);
  }
  if (!run.empty()) runs.push_back(std::move(run));
  return runs;
}

double length(const std::vector<Node>& run) {
  double l = 0.0;
  for (std::size_t i = 1; i < run.size(); ++i) l += distance(run[i - 1], run[i]);
  return l;
}

// The middle of a thin ring between OUTER and HOLE (mm, each a closed loop): for each point of
// OUTER, the midpoint to the nearest point of HOLE, with half that distance as the half width; in
// OUTER's order (the loop closes from the last back to the first). A wall narrower than a bead is
// a thin ring, so this is its centre line. (The straight skeleton of an even ring collapses
// everywhere at once, which costs CGAL its exact arithmetic: tens of milliseconds a layer.)
std::vector<Node> loop_round_hole(const std::vector<Kernel::Point_2>& outer, const std::vector<Kernel::Point_2>& hole) {
  std::vector<Node> loop;
  const std::size_t m = hole.size();
  for (const Kernel::Point_2& o : outer) {
    const double ox = o.x(), oy = o.y();
    double best = std::numeric_limits<double>::infinity(), bx = 0.0, by = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const Kernel::Point_2 &a = hole[j], &b = hole[(j + 1) % m];
      const double dx = b.x() - a.x(), dy = b.y() - a.y(), l2 = dx * dx + dy * dy;
      const double t = l2 > 0.0 ? std::clamp(((ox - a.x()) * dx + (oy - a.y()) * dy) / l2, 0.0, 1.0) : 0.0;
      const double px = a.x() + t * dx, py = a.y() + t * dy, d = std::hypot(ox - px, oy - py);
      if (d < best) best = d, bx = px, by = py;
    }
    loop.push_back({(ox + bx) / 2.0, (oy + by) / 2.0, best / 2.0});
  }
  return loop;
}

// The points of RING (units) simplified (kSimplifyMm, geom2d::simplified), in mm from ORIGIN,
// without repeats.
std::vector<Kernel::Point_2> outline(const geom2d::Ring& ring, geom2d::Point origin) {
  std::vector<Kernel::Point_2> points;
  for (const geom2d::Point& p : geom2d::simplified(ring, kSimplifyMm)) {
    const Kernel::Point_2 q(geom2d::to_mm(p.x - origin.x), geom2d::to_mm(p.y - origin.y));
    if (points.empty() || q != points.back()) points.push_back(q);
  }
  while (points.size() > 1 && points.front() == points.back()) points.pop_back();
  return points;
}

}  // namespace

std::vector<geom2d::Ring> centre_lines(const geom2d::Polygon& piece, double bead_mm, double min_width_mm) {
  if (piece.holes.size() > 1 || piece.outer.size() < 3) return {};
  const geom2d::Point origin = piece.outer.front();
  const std::vector<Kernel::Point_2> points = outline(piece.outer, origin);
  std::vector<std::vector<Kernel::Point_2>> holes;
  std::size_t sides = points.size();
  for (const geom2d::Ring& h : piece.holes) holes.push_back(outline(h, origin)), sides += holes.back().size();
  if (points.size() < 3 || sides > kMaxSides) return {};
  for (const auto& h : holes) {
    if (h.size() < 3) return {};
  }
  std::vector<Node> path;
  if (holes.empty()) {
    // The longest path through the skeleton's tree.
    std::vector<Node> nodes;
    std::vector<std::vector<Edge>> edges;
    if (!skeleton(points, nodes, edges)) return {};
    std::vector<std::size_t> parent;
    const std::size_t a = farthest(edges, 0, parent);
    const std::size_t b = farthest(edges, a, parent);
    for (std::size_t n = b; n != SIZE_MAX; n = parent[n]) path.push_back(nodes[n]);
  } else {
    // Round the hole, closed; opened at its narrowest point when that is under the width, so that
    // the runs are the parts wide enough.
    const std::vector<Node> loop = loop_round_hole(points, holes.front());
    if (loop.size() < 3) return {};
    std::size_t narrowest = 0;
    for (std::size_t i = 1; i < loop.size(); ++i) {
      if (loop[i].r < loop[narrowest].r) narrowest = i;
    }
    const std::size_t first = loop[narrowest].r < min_width_mm / 2.0 ? narrowest : 0;
    for (std::size_t i = 0; i <= loop.size(); ++i) path.push_back(loop[(first + i) % loop.size()]);
  }
  std::vector<geom2d::Ring> lines;
  for (const std::vector<Node>& run : wide_runs(path, min_width_mm / 2.0)) {
    if (length(run) < kMinRunBeads * bead_mm) continue;
    geom2d::Ring line;
    for (const Node& n : run) {
      const geom2d::Point p{origin.x + geom2d::to_units(n.x), origin.y + geom2d::to_units(n.y)};
      if (line.empty() || !(p == line.back())) line.push_back(p);
    }
    if (line.size() >= 2) lines.push_back(std::move(line));
  }
  return lines;
}

std::vector<geom2d::Ring> lines_within(const std::vector<geom2d::Ring>& lines, const std::vector<geom2d::Polygon>& polygons, double bead_mm) {
  std::vector<geom2d::Ring> out;
  for (geom2d::Ring& line : geom2d::clip_open(lines, geom2d::rings_of(polygons))) {
    double l = 0.0;
    for (std::size_t i = 1; i < line.size(); ++i) {
      l += std::hypot(geom2d::to_mm(line[i].x - line[i - 1].x), geom2d::to_mm(line[i].y - line[i - 1].y));
    }
    if (line.size() >= 2 && l >= kMinRunBeads * bead_mm) out.push_back(std::move(line));
  }
  return out;
}

}  // namespace polyaxis::toolpath::detail
