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

// Where the plane crosses face F: the above-to-below half-edge where the segment starts and the
// below-to-above one where it ends, under the tie rule (a corner is above when its height is >= h).
struct Segment {
  std::uint32_t start_he = kNoHalfEdge;
  std::uint32_t end_he = kNoHalfEdge;
  bool crossed() const { return start_he != kNoHalfEdge; }
};

Segment segment_of(const SectionContext& ctx, std::uint32_t f, double h) {
  const auto& t = ctx.mesh().triangles[f];
  const bool above[3] = {ctx.height(t[0]) >= h, ctx.height(t[1]) >= h, ctx.height(t[2]) >= h};
  Segment s;
  if (above[0] == above[1] && above[1] == above[2]) return s;
  for (std::uint32_t k = 0; k < 3; ++k) {
    if (above[k] && !above[(k + 1) % 3]) s.start_he = 3 * f + k;
    if (!above[k] && above[(k + 1) % 3]) s.end_he = 3 * f + k;
  }
  return s;
}

// Where FIELD_AT meets LEVEL on the edge PA → PB, as a parameter in (0, 1): regula falsi
// (Illinois) from the linear estimate T, with RA and RB the field less the level at the ends
// (opposite signs). Stops within kExactCrossingMm of the level or after kExactCrossingSteps.
constexpr double kExactCrossingMm = 1e-5;
constexpr int kExactCrossingSteps = 12;

double exact_crossing(const std::function<double(Vec3)>& field_at, double level, Vec3 pa, Vec3 pb, double ra, double rb, double t) {
  double lo = 0.0, hi = 1.0;
  int kept = 0;  // which end was kept last time: -1 lo, +1 hi
  for (int it = 0; it < kExactCrossingSteps; ++it) {
    const double r = field_at(pa + (pb - pa) * t) - level;
    if (std::fabs(r) <= kExactCrossingMm) break;
    if ((r < 0.0) == (ra < 0.0)) {
      lo = t, ra = r;
      if (kept == -1) rb *= 0.5;
      kept = -1;
    } else {
      hi = t, rb = r;
      if (kept == 1) ra *= 0.5;
      kept = 1;
    }
    t = lo + (hi - lo) * ra / (ra - rb);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  }
  return t;
}

// The crossing of half-edge H with the plane, in (u, v) units. Built from the edge's ends in
// vertex-index order, so both faces of the edge get the same point bit for bit.
geom2d::Point crossing(const SectionContext& ctx, const Frame& frame, std::uint32_t h, double plane) {
  const mesh::Mesh& m = ctx.mesh();
  std::uint32_t a = mesh::half_edge_from(m, h), b = mesh::half_edge_to(m, h);
  if (a > b) std::swap(a, b);
  const double sa = ctx.height(a), sb = ctx.height(b);
  double t = (plane - sa) / (sb - sa);  // sa != sb: the ends lie on opposite sides
  const Vec3 pa = m.vertices[a], pb = m.vertices[b];
  if (ctx.field_at()) t = exact_crossing(ctx.field_at(), plane, pa, pb, sa - plane, sb - plane, t);
  const Vec3 p = pa + (pb - pa) * t - frame.origin;
  return {geom2d::to_units(core::dot(p, frame.u)), geom2d::to_units(core::dot(p, frame.v))};
}

// A fresh epoch of SCRATCH's face stamps for a mesh of NF faces.
std::uint32_t next_epoch(SectionScratch& scratch, std::size_t nf) {
  if (scratch.stamp.size() != nf || scratch.epoch == 0xffffffffu) {
    scratch.stamp.assign(nf, 0);
    scratch.epoch = 0;
  }
  return ++scratch.epoch;
}

}  // namespace

// Loops are walked face to face: the segment of face f ends on a half-edge whose twin starts the
// segment of the next face, so a loop needs no search. Loops start at the first candidate of each,
// in candidate order.
SectionResult section(const SectionContext& ctx, double h, const Frame& frame, std::span<const std::uint32_t> candidates,
                      SectionScratch& scratch) {
  const auto& opposite = ctx.topology().opposite;
  const std::uint32_t epoch = next_epoch(scratch, ctx.mesh().triangles.size());
  auto& stamp = scratch.stamp;
  SectionResult result;
  std::vector<geom2d::Ring> rings;
  geom2d::Ring ring;
  for (const std::uint32_t first : candidates) {
    if (stamp[first] == epoch) continue;
    stamp[first] = epoch;
    Segment s = segment_of(ctx, first, h);
    if (!s.crossed()) continue;
    ring.clear();
    bool closed = false;
    while (true) {
      const geom2d::Point p = crossing(ctx, frame, s.start_he, h);
      if (ring.empty() || !(ring.back() == p)) ring.push_back(p);
      const std::uint32_t twin = opposite[s.end_he];
      if (twin == kNoHalfEdge) break;
      const std::uint32_t g = twin / 3;
      if (g == first) {
        closed = segment_of(ctx, g, h).start_he == twin;
        break;
      }
      if (stamp[g] == epoch) break;
      const Segment next = segment_of(ctx, g, h);
      if (next.start_he != twin) break;  // a face turned the other way: the chain is open
      stamp[g] = epoch;
      s = next;
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
