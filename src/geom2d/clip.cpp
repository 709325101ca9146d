#include "polyaxis/geom2d/clip.h"

#include <polyclipping/clipper.hpp>

#include "ring_nesting.h"

#include <algorithm>
#include <cmath>

namespace polyaxis::geom2d {
namespace {

// A bead's footprint is drawn with its round ends and joins this close to true (mm): a few dozen
// points a half turn for a 1 mm bead.
constexpr double kSweepArcToleranceMm = 2e-3;

ClipperLib::Path to_path(const Ring& ring) {
  ClipperLib::Path path;
  path.reserve(ring.size());
  for (const Point& p : ring) path.emplace_back(p.x, p.y);
  return path;
}

Ring to_ring(const ClipperLib::Path& path) {
  Ring ring;
  ring.reserve(path.size());
  for (const auto& p : path) ring.push_back({p.X, p.Y});
  return ring;
}

std::vector<Polygon> from_tree(const ClipperLib::PolyTree& tree) {
  std::vector<Polygon> out;
  // Outer rings are the even-depth nodes; their children are holes.
  std::vector<const ClipperLib::PolyNode*> stack(tree.Childs.begin(), tree.Childs.end());
  while (!stack.empty()) {
    const ClipperLib::PolyNode* node = stack.back();
    stack.pop_back();
    Polygon poly;
    poly.outer = to_ring(node->Contour);
    for (const ClipperLib::PolyNode* hole : node->Childs) {
      poly.holes.push_back(to_ring(hole->Contour));
      for (const ClipperLib::PolyNode* island : hole->Childs) stack.push_back(island);
    }
    out.push_back(std::move(poly));
  }
  detail::finish_polygons(out);
  return out;
}

}  // namespace

namespace {

// Clipper's output never has crossing edges, but a ring may touch itself or another at a vertex:
// a vertex that appears twice, found with a hash set (open addressing at load <= 1/2).
bool has_touching_vertices(const std::vector<Polygon>& polys) {
  std::size_t count = 0;
  for (const Polygon& p : polys) {
    count += p.outer.size();
    for (const Ring& h : p.holes) count += h.size();
  }
  std::size_t capacity = 16;
  while (capacity < 2 * count) capacity *= 2;
  thread_local std::vector<const Point*> slots;
  slots.assign(capacity, nullptr);
  const std::uint64_t mask = capacity - 1;
  auto seen_before = [&](const Point& q) {
    std::uint64_t h = static_cast<std::uint64_t>(q.x) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(q.y) * 0xC2B2AE3D27D4EB4FULL;
    h ^= h >> 31;
    for (std::uint64_t s = h & mask;; s = (s + 1) & mask) {
      if (slots[s] == nullptr) {
        slots[s] = &q;
        return false;
      }
      if (*slots[s] == q) return true;
    }
  };
  for (const Polygon& p : polys) {
    for (const Point& q : p.outer) {
      if (seen_before(q)) return true;
    }
    for (const Ring& h : p.holes) {
      for (const Point& q : h) {
        if (seen_before(q)) return true;
      }
    }
  }
  return false;
}

std::vector<Polygon> union_impl(const std::vector<Ring>& rings, FillRule fill_rule, bool strictly_simple) {
  ClipperLib::Clipper clipper;
  clipper.StrictlySimple(strictly_simple);
  for (const Ring& r : rings) {
    if (r.size() >= 3) clipper.AddPath(to_path(r), ClipperLib::ptSubject, true);
  }
  ClipperLib::PolyTree tree;
  const auto rule = fill_rule == FillRule::kNonZero ? ClipperLib::pftNonZero : ClipperLib::pftEvenOdd;
  clipper.Execute(ClipperLib::ctUnion, tree, rule, rule);
  return from_tree(tree);
}

}  // namespace

std::vector<Polygon> union_rings(const std::vector<Ring>& rings, FillRule fill_rule) {
  // Sections of a clean mesh need no boolean (ring_nesting.h): the same polygons, without Clipper.
  if (auto nested = detail::union_of_nested_rings(rings)) return std::move(*nested);
  return detail::union_rings_by_clipper(rings, fill_rule);
}

std::vector<Polygon> detail::union_rings_by_clipper(const std::vector<Ring>& rings, FillRule fill_rule) {
  // Clipper's strictly-simple pass is quadratic in a ring's points: run it only when the plain
  // union left rings touching at a vertex, which sections of a clean mesh almost never do.
  std::vector<Polygon> result = union_impl(rings, fill_rule, false);
  if (has_touching_vertices(result)) result = union_impl(rings, fill_rule, true);
  return result;
}

std::vector<Ring> union_boundary(const std::vector<Ring>& rings, FillRule fill_rule) {
  // Rings that nest without crossing are their own union's boundary (ring_nesting.h).
  if (detail::union_of_nested_rings(rings)) return rings;
  ClipperLib::Clipper clipper;
  for (const Ring& r : rings) {
    if (r.size() >= 3) clipper.AddPath(to_path(r), ClipperLib::ptSubject, true);
  }
  ClipperLib::Paths paths;  // not a PolyTree: nesting its rings is what costs
  const auto rule = fill_rule == FillRule::kNonZero ? ClipperLib::pftNonZero : ClipperLib::pftEvenOdd;
  clipper.Execute(ClipperLib::ctUnion, paths, rule, rule);
  std::vector<Ring> out;
  out.reserve(paths.size());
  for (const ClipperLib::Path& path : paths) out.push_back(to_ring(path));
  return out;
}

namespace {

std::vector<Polygon> boolean(ClipperLib::ClipType op, const std::vector<Ring>& a, const std::vector<Ring>& b) {
  ClipperLib::Clipper clipper;
  // Only areas of these results are used: no strictly-simple pass needed.
  for (const Ring& r : a) {
    if (r.size() >= 3) clipper.AddPath(to_path(r), ClipperLib::ptSubject, true);
  }
  for (const Ring& r : b) {
    if (r.size() >= 3) clipper.AddPath(to_path(r), ClipperLib::ptClip, true);
  }
  ClipperLib::PolyTree tree;
  clipper.Execute(op, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return from_tree(tree);
}

}  // namespace

std::vector<Polygon> xor_rings(const std::vector<Ring>& a, const std::vector<Ring>& b) { return boolean(ClipperLib::ctXor, a, b); }
std::vector<Polygon> difference_rings(const std::vector<Ring>& a, const std::vector<Ring>& b) {
  return boolean(ClipperLib::ctDifference, a, b);
}

std::vector<Polygon> intersection_rings(const std::vector<Ring>& a, const std::vector<Ring>& b) {
  return boolean(ClipperLib::ctIntersection, a, b);
}

std::vector<Polygon> sweep_open(const std::vector<Ring>& paths, double radius_mm) {
  ClipperLib::ClipperOffset off(2.0, kSweepArcToleranceMm * kUnitsPerMm);
  for (const Ring& r : paths) {
    if (!r.empty()) off.AddPath(to_path(r), ClipperLib::jtRound, ClipperLib::etOpenRound);
  }
  ClipperLib::PolyTree tree;
  off.Execute(tree, radius_mm * kUnitsPerMm);
  return from_tree(tree);
}

std::vector<Ring> clip_open(const std::vector<Ring>& paths, const std::vector<Ring>& rings) {
  ClipperLib::Clipper clipper;
  for (const Ring& p : paths) {
    if (p.size() >= 2) clipper.AddPath(to_path(p), ClipperLib::ptSubject, false);
  }
  for (const Ring& r : rings) {
    if (r.size() >= 3) clipper.AddPath(to_path(r), ClipperLib::ptClip, true);
  }
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  ClipperLib::Paths open;
  ClipperLib::OpenPathsFromPolyTree(tree, open);
  std::vector<Ring> out;
  for (const auto& p : open) out.push_back(to_ring(p));
  return out;
}

std::vector<Polygon> offset(const std::vector<Polygon>& polygons, double delta_mm) { return offset_rings(rings_of(polygons), delta_mm); }

std::vector<Polygon> offset_rings(const std::vector<Ring>& rings, double delta_mm) {
  ClipperLib::ClipperOffset off(2.0, 0.25 * kUnitsPerMm * 1e-3);
  for (const Ring& r : rings) off.AddPath(to_path(r), ClipperLib::jtMiter, ClipperLib::etClosedPolygon);
  ClipperLib::PolyTree tree;
  off.Execute(tree, delta_mm * kUnitsPerMm);
  return from_tree(tree);
}

}  // namespace polyaxis::geom2d
