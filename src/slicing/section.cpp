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

SectionContext::SectionContext(const mesh::Mesh& mesh, Vec3 direction)
    : mesh_(mesh), topology_(mesh::build_topology(mesh)), d_(core::normalized(direction)) {
  height_.resize(mesh.vertices.size());
  min_ = INFINITY;
  max_ = -INFINITY;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    height_[i] = core::dot(mesh.vertices[i], d_);
    min_ = std::min(min_, height_[i]);
    max_ = std::max(max_, height_[i]);
  }
  face_min_.resize(mesh.triangles.size());
  face_max_.resize(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const double a = height_[t[0]], b = height_[t[1]], c = height_[t[2]];
    face_min_[f] = std::min({a, b, c});
    face_max_[f] = std::max({a, b, c});
  }
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
    if (!(ctx.face_min(f) < h && h <= ctx.face_max(f))) continue;  // the tie rule, per face
    Segment s{kNoHalfEdge, kNoHalfEdge};
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t he = 3 * f + k;
      const bool from_above = ctx.height(mesh::half_edge_from(m, he)) >= h;
      const bool to_above = ctx.height(mesh::half_edge_to(m, he)) >= h;
      if (from_above && !to_above) s.start_he = he;
      if (!from_above && to_above) s.end_he = he;
    }
    segments.push_back(s);
  }
  if (segments.empty()) return result;
  auto& start_of = scratch.segment_of_start;
  if (start_of.size() < opposite.size()) start_of.assign(opposite.size(), kNoHalfEdge);
  for (std::uint32_t i = 0; i < segments.size(); ++i) start_of[segments[i].start_he] = i;

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
      const std::uint32_t next = twin == kNoHalfEdge ? kNoHalfEdge : start_of[twin];
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
  for (const Segment& s : segments) start_of[s.start_he] = kNoHalfEdge;  // leave the scratch clean
  result.polygons = geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
  for (const auto& p : result.polygons) result.area_mm2 += geom2d::area_mm2(p);
  return result;
}

}  // namespace polyaxis::slicing
