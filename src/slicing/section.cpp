#include "polyaxis/slicing/section.h"

#include <algorithm>
#include <cmath>

#include "polyaxis/geom2d/clip.h"

namespace polyaxis::slicing {

using mesh::kNoHalfEdge;

Frame plane_frame(Vec3 direction, double height_mm) {
  Frame f;
  f.d = core::normalized(direction);
  const Vec3 ref = std::fabs(f.d.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  f.u = core::normalized(ref - f.d * core::dot(ref, f.d));
  f.v = core::cross(f.d, f.u);
  f.origin = f.d * height_mm;
  return f;
}

SectionContext::SectionContext(const mesh::Mesh& mesh, Vec3 direction, const mesh::EdgeTopology* topology)
    : mesh_(mesh), topology_(topology), d_(core::normalized(direction)) {
  if (topology_ == nullptr) own_topology_ = mesh::build_topology(mesh);
  height_.resize(mesh.vertices.size());
  min_ = INFINITY;
  max_ = -INFINITY;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    height_[i] = core::dot(mesh.vertices[i], d_);
    min_ = std::min(min_, height_[i]);
    max_ = std::max(max_, height_[i]);
  }
}

SectionContext::SectionContext(const mesh::Mesh& mesh, Vec3 direction, std::vector<double> field, const mesh::EdgeTopology* topology)
    : mesh_(mesh), topology_(topology), d_(core::normalized(direction)), height_(std::move(field)) {
  if (topology_ == nullptr) own_topology_ = mesh::build_topology(mesh);
  height_.resize(mesh.vertices.size(), 0.0);
  min_ = INFINITY;
  max_ = -INFINITY;
  for (const double h : height_) min_ = std::min(min_, h), max_ = std::max(max_, h);
}

namespace {

struct Segment {
  std::uint32_t start_he;  // the above-to-below half-edge where the segment starts
  std::uint32_t end_he;    // the below-to-above half-edge where it ends
};

// The crossing of half-edge H with the plane, in (u, v) units. Built from the edge's ends in
// vertex-index order, so both faces of the edge get the same point bit for bit.
geom2d::Point crossing(const SectionContext& ctx, const Frame& frame, std::uint32_t h, double plane) {
  const mesh::Mesh& m = ctx.mesh();
  std::uint32_t a = mesh::half_edge_from(m, h), b = mesh::half_edge_to(m, h);
  if (a > b) std::swap(a, b);
  const double sa = ctx.height(a), sb = ctx.height(b);
  const double t = (plane - sa) / (sb - sa);  // sa != sb: the ends lie on opposite sides
  const Vec3 pa = m.vertices[a], pb = m.vertices[b];
  const Vec3 p = pa + (pb - pa) * t - frame.origin;
  return {geom2d::to_units(core::dot(p, frame.u)), geom2d::to_units(core::dot(p, frame.v))};
}

}  // namespace

SectionResult section(const SectionContext& ctx, double h, const Frame& frame, std::span<const std::uint32_t> candidates,
                      SectionScratch& scratch) {
  const mesh::Mesh& m = ctx.mesh();
  const auto& opposite = ctx.topology().opposite;
  SectionResult result;
  std::vector<Segment> segments;
  for (const std::uint32_t f : candidates) {
    // The tie rule, once per corner: a corner is above when its height is >= h.
    const auto& t = m.triangles[f];
    const bool above[3] = {ctx.height(t[0]) >= h, ctx.height(t[1]) >= h, ctx.height(t[2]) >= h};
    if (above[0] == above[1] && above[1] == above[2]) continue;  // not crossed
    Segment s{kNoHalfEdge, kNoHalfEdge};
    for (std::uint32_t k = 0; k < 3; ++k) {
      const bool from_above = above[k], to_above = above[(k + 1) % 3];
      if (from_above && !to_above) s.start_he = 3 * f + k;
      if (!from_above && to_above) s.end_he = 3 * f + k;
    }
    segments.push_back(s);
  }
  if (segments.empty()) return result;
  // Map from starting half-edge to segment: open addressing at load <= 1/2.
  constexpr std::uint64_t kFree = ~std::uint64_t{0};
  std::size_t capacity = 64;
  while (capacity < 2 * segments.size()) capacity *= 2;
  auto& slots = scratch.slots;
  slots.assign(capacity, kFree);
  const std::uint64_t mask = capacity - 1;
  auto slot_hash = [](std::uint32_t he) { return (static_cast<std::uint64_t>(he) * 0x9E3779B97F4A7C15ULL) >> 20; };
  for (std::uint32_t i = 0; i < segments.size(); ++i) {
    std::uint64_t s = slot_hash(segments[i].start_he) & mask;
    while (slots[s] != kFree) s = (s + 1) & mask;
    slots[s] = (static_cast<std::uint64_t>(segments[i].start_he) << 32) | i;
  }
  auto start_of = [&](std::uint32_t he) -> std::uint32_t {
    for (std::uint64_t s = slot_hash(he) & mask; slots[s] != kFree; s = (s + 1) & mask) {
      if ((slots[s] >> 32) == he) return static_cast<std::uint32_t>(slots[s]);
    }
    return kNoHalfEdge;
  };

  std::vector<char> used(segments.size(), 0);
  std::vector<geom2d::Ring> rings;
  geom2d::Ring ring;
  for (std::uint32_t first = 0; first < segments.size(); ++first) {
    if (used[first]) continue;
    ring.clear();
    std::uint32_t i = first;
    bool closed = false;
    while (true) {
      used[i] = 1;
      const geom2d::Point p = crossing(ctx, frame, segments[i].start_he, h);
      if (ring.empty() || !(ring.back() == p)) ring.push_back(p);
      const std::uint32_t twin = opposite[segments[i].end_he];
      const std::uint32_t next = twin == kNoHalfEdge ? kNoHalfEdge : start_of(twin);
      if (next == first) {
        closed = true;
        break;
      }
      if (next == kNoHalfEdge || used[next]) break;
      i = next;
    }
    if (!closed) {
      ++result.open_chains;
      continue;
    }
    while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    if (ring.size() >= 3) rings.push_back(std::move(ring));
    ring = geom2d::Ring();
  }
  result.polygons = geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
  for (const auto& p : result.polygons) result.area_mm2 += geom2d::area_mm2(p);
  return result;
}

std::vector<geom2d::Polygon> project(const std::vector<geom2d::Polygon>& polygons, const Frame& from, const Frame& to) {
  std::vector<geom2d::Ring> rings;
  for (const geom2d::Ring& ring : geom2d::rings_of(polygons)) {
    geom2d::Ring out;
    out.reserve(ring.size());
    for (const geom2d::Point& q : ring) {
      const Vec3 w = from.to_world(geom2d::to_mm(q.x), geom2d::to_mm(q.y)) - to.origin;
      out.push_back({geom2d::to_units(core::dot(w, to.u)), geom2d::to_units(core::dot(w, to.v))});
    }
    rings.push_back(std::move(out));
  }
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

}  // namespace polyaxis::slicing
