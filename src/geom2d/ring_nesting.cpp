#include "ring_nesting.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace polyaxis::geom2d::detail {
namespace {

// Exact tests allowed per point (edge pairs sharing a cell, ring points of containment tests),
// plus a constant, before the question is left to the boolean; and cells an edge may be entered
// in, on average.
constexpr std::size_t kTestsPerPoint = 32;
constexpr std::size_t kTestsSlack = 4096;
constexpr std::size_t kCellsPerEdge = 8;

struct Box {
  std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
  void add(Point p) { x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y); }
  bool holds(const Box& o) const { return x0 <= o.x0 && y0 <= o.y0 && o.x1 <= x1 && o.y1 <= y1; }
};

Point lowest(const Ring& ring) {
  Point best = ring.front();
  for (const Point& p : ring) {
    if (p.y < best.y || (p.y == best.y && p.x < best.x)) best = p;
  }
  return best;
}

bool lower(Point a, Point b) { return a.y != b.y ? a.y < b.y : a.x < b.x; }

void canonical_start(Ring& ring) {
  if (ring.empty()) return;
  const Point start = lowest(ring);
  std::rotate(ring.begin(), std::find(ring.begin(), ring.end(), start), ring.end());
}

// At least three points, no two consecutive ones equal, no three consecutive ones collinear.
bool clean(const Ring& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Point a = ring[i], b = ring[(i + 1) % n], c = ring[(i + 2) % n];
    if (a == b || orientation(a, b, c) == 0) return false;
  }
  return true;
}

// True when no two edges of RINGS share a point but adjacent edges of one ring their common
// point: each edge entered in the cells of its box on a grid over BOX about as wide as an edge is
// long (two edges sharing a point share that point's cell), every pair of edges sharing a cell
// tested exactly. False too when that would take more than
// BUDGET tests or too many cell entries.
bool edges_apart(const std::vector<Ring>& rings, const Box& box, std::size_t edges, std::size_t budget) {
  double extent = 0.0;
  for (const Ring& ring : rings) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Point a = ring[i], b = ring[(i + 1) % ring.size()];
      extent += static_cast<double>(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)));
    }
  }
  const double width = static_cast<double>(box.x1) - static_cast<double>(box.x0), height = static_cast<double>(box.y1) - static_cast<double>(box.y0);
  // About an edge's length, but no more cells than kCellsPerEdge an edge.
  const double side = std::max({1.0, extent / static_cast<double>(edges),
                                std::sqrt(width * height / static_cast<double>(kCellsPerEdge * edges)),
                                std::max(width, height) / static_cast<double>(kCellsPerEdge * edges)});
  const auto nx = static_cast<std::size_t>(width / side) + 1, ny = static_cast<std::size_t>(height / side) + 1;
  // The cell of a coordinate grows with it (a product with a positive constant, rounded): two
  // edges with a common point share that point's cell.
  const double per_side = 1.0 / side;
  auto column = [&](std::int64_t x) { return std::min(nx - 1, static_cast<std::size_t>((static_cast<double>(x) - static_cast<double>(box.x0)) * per_side)); };
  auto row = [&](std::int64_t y) { return std::min(ny - 1, static_cast<std::size_t>((static_cast<double>(y) - static_cast<double>(box.y0)) * per_side)); };
  thread_local std::vector<std::uint32_t> head, next;
  thread_local std::vector<std::array<std::uint32_t, 2>> edge_of;  // entry -> (ring, index)
  thread_local std::vector<std::uint32_t> used;                    // cells with entries
  head.assign(nx * ny, UINT32_MAX);
  next.clear(), edge_of.clear(), used.clear();
  const std::size_t max_entries = kCellsPerEdge * edges + kTestsSlack;
  for (std::uint32_t r = 0; r < rings.size(); ++r) {
    const Ring& ring = rings[r];
    for (std::uint32_t i = 0; i < ring.size(); ++i) {
      const Point a = ring[i], b = ring[(i + 1) % ring.size()];
      const std::size_t x0 = column(std::min(a.x, b.x)), x1 = column(std::max(a.x, b.x));
      const std::size_t y0 = row(std::min(a.y, b.y)), y1 = row(std::max(a.y, b.y));
      if (next.size() + (x1 - x0 + 1) * (y1 - y0 + 1) > max_entries) return false;
      for (std::size_t y = y0; y <= y1; ++y) {
        for (std::size_t x = x0; x <= x1; ++x) {
          std::uint32_t& h = head[y * nx + x];
          if (h == UINT32_MAX) used.push_back(static_cast<std::uint32_t>(y * nx + x));
          next.push_back(h);
          h = static_cast<std::uint32_t>(edge_of.size());
          edge_of.push_back({r, i});
        }
      }
    }
  }
  std::size_t tests = 0;
  for (const std::uint32_t c : used) {
    for (std::uint32_t p = head[c]; p != UINT32_MAX; p = next[p]) {
      const auto [er, ei] = edge_of[p];
      const Ring& re = rings[er];
      const auto ne = static_cast<std::uint32_t>(re.size());
      for (std::uint32_t q = next[p]; q != UINT32_MAX; q = next[q]) {
        const auto [fr, fi] = edge_of[q];
        // Adjacent edges of a ring meet at their common point only (no three consecutive points collinear).
        if (er == fr && ((ei + 1) % ne == fi || (fi + 1) % ne == ei)) continue;
        if (++tests > budget) return false;
        const Ring& rf = rings[fr];
        if (segments_touch(re[ei], re[(ei + 1) % ne], rf[fi], rf[(fi + 1) % rf.size()])) return false;
      }
    }
  }
  return true;
}

// P strictly inside RING (P is on no edge of it: the rings touch nowhere).
bool inside(Point p, const Ring& ring) {
  bool in = false;
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
    const Point a = ring[i], b = ring[(i + 1) % n];
    if ((a.y > p.y) != (b.y > p.y)) {
      // The edge crosses the ray from P along +x when P lies on its left going up, on its right going down.
      if ((orientation(a, b, p) > 0) == (b.y > a.y)) in = !in;
    }
  }
  return in;
}

}  // namespace

void finish_polygons(std::vector<Polygon>& polygons) {
  for (Polygon& poly : polygons) {
    if (twice_signed_area(poly.outer) < 0) std::reverse(poly.outer.begin(), poly.outer.end());
    canonical_start(poly.outer);
    for (Ring& h : poly.holes) {
      if (twice_signed_area(h) > 0) std::reverse(h.begin(), h.end());
      canonical_start(h);
    }
    std::sort(poly.holes.begin(), poly.holes.end(), [](const Ring& a, const Ring& b) { return lower(lowest(a), lowest(b)); });
  }
  std::sort(polygons.begin(), polygons.end(), [](const Polygon& a, const Polygon& b) { return lower(lowest(a.outer), lowest(b.outer)); });
}

std::optional<std::vector<Polygon>> union_of_nested_rings(const std::vector<Ring>& rings) {
  std::size_t points = 0;
  std::vector<Box> boxes(rings.size());
  Box all;
  for (std::size_t i = 0; i < rings.size(); ++i) {
    if (!clean(rings[i])) return std::nullopt;
    points += rings[i].size();
    for (const Point& p : rings[i]) boxes[i].add(p);
    all.add({boxes[i].x0, boxes[i].y0}), all.add({boxes[i].x1, boxes[i].y1});
  }
  if (rings.empty()) return std::vector<Polygon>{};
  const std::size_t budget = kTestsPerPoint * points + kTestsSlack;
  if (!edges_apart(rings, all, points, budget)) return std::nullopt;
  // Nesting: ring I lies in ring J when J's box holds I's and I's first point is inside J.
  const std::size_t k = rings.size();
  std::vector<std::size_t> depth(k, 0);
  std::vector<std::optional<std::size_t>> parent(k);
  std::size_t tests = 0;
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < k; ++j) {
      if (++tests > budget) return std::nullopt;
      if (j == i || !boxes[j].holds(boxes[i])) continue;
      tests += rings[j].size();
      if (!inside(rings[i].front(), rings[j])) continue;
      ++depth[i];
      // The containers of a ring lie in one another: the deepest is the one around it.
      if (!parent[i] || boxes[*parent[i]].holds(boxes[j])) parent[i] = j;
    }
  }
  for (std::size_t i = 0; i < k; ++i) {
    const bool ccw = twice_signed_area(rings[i]) > 0;
    if (ccw != (depth[i] % 2 == 0)) return std::nullopt;
  }
  std::vector<Polygon> out;
  std::vector<std::size_t> polygon_of(k, 0);
  for (std::size_t i = 0; i < k; ++i) {
    if (depth[i] % 2 != 0) continue;
    polygon_of[i] = out.size();
    out.push_back({rings[i], {}});
  }
  for (std::size_t i = 0; i < k; ++i) {
    if (depth[i] % 2 != 0) out[polygon_of[*parent[i]]].holes.push_back(rings[i]);
  }
  finish_polygons(out);
  return out;
}

}  // namespace polyaxis::geom2d::detail
