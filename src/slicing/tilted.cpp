// Tilted "3-D" layers (Ruan et al. 2006, §4.2.2).
//
// The first layer is planar, normal to the slicing direction, its plane half a layer above the
// part's lowest point (as the planar slicers put it). Every next layer is a plane chosen along the
// centroidal axis of the sections: with c the centroid of the previous section (a node of the
// axis), n its plane's normal and Δ the step, the axis's next link L runs from c to the centroid
// of the section parallel to the previous plane at Δ above it; the tentative plane passes through
// P_upper = c + D·Δ with normal D = L (so the thickness on the axis is Δ). It is accepted when
//   - its section is not empty;
//   - the thickness at every corner p of the section, the distance along D from p down to the
//     previous plane, t(p) = ((p − o)·n) / (D·n), lies in [ΔL_min, ΔL_max];
//   - every corner of the previous section lies at least ΔL_min/2 under the plane (the two planes
//     do not meet inside the part, whatever the shape does beyond this section);
//   - VolDiff ≤ VolDiff_pre (Eq. 9) with the normalisation of adaptive.cpp,
//     A(S_b Δ S_t) / max(A(S_b), A(S_t)), S_b projected along D onto the plane;
//   - the overhang limit of adaptive.cpp: S_t within S_b (projected) grown by
//     max(t_min·tan α, step).
// Otherwise D ← (D + n)/2 (Ruan's steps 1–2) until D is within kEpsDeg of n, then Δ ← Δ − Δ/4
// (step 3), from the nominal step down to ΔL_min (the middle of the range tried second). When no
// plane passes, the one turned furthest that keeps the thickness and the order of the planes (the
// turn bisected as for a passing one) is taken (VolDiff and the overhang given up
// for it, so that the layers keep turning towards the axis: a tube leaning 70° is reached in a few
// dozen layers), else the plane parallel to the previous one at ΔL_min; both are counted in
// limit_violations (as the adaptive slicer counts its own).
// The layers end where the section parallel to the previous plane at ΔL_min is empty.
//
// Every trial cuts the mesh along its own direction: O(V) for the heights plus the faces of the
// clusters the plane passes through (Cutter); a layer takes a few.
#include "tilted.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::slicing::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Ruan's ε: the turn towards the previous normal stops halving below this angle.
constexpr double kEpsDeg = 0.05;
// Δ ← Δ − Δ/4.
constexpr double kShrink = 0.25;
// Snapping noise in the overhang difference (as adaptive.cpp).
constexpr double kOverhangAreaMm2 = 1e-3;
// Every corner of the previous section stays this share of ΔL_min under the next plane.
constexpr double kUnderShare = 0.5;
// The layers must cover at least this share of the part's volume (Σ area × thickness on the axis
// comes within 0.5 % on parts the planes follow).
constexpr double kCoveredShare = 0.97;
// Rounding of the thickness test (mm): corners are rounded to the polygon grid.
constexpr double kThicknessSlackMm = 1e-6;

// A section by an arbitrary plane {p : p·n = h}, with what the tests need of it.
struct Cut {
  Frame frame;
  double h = 0.0;
  SectionResult s;
  Vec3 centroid;
  std::vector<Vec3> corners;  // world positions of every ring vertex
  bool empty() const { return s.polygons.empty() || s.area_mm2 <= 0.0; }
};

// Cuts the mesh by arbitrary planes. Faces are kept in spatial clusters (Morton order of their
// centroids, kClusterFaces a cluster) with bounding spheres, so a cut visits only the clusters
// its plane passes through.
class Cutter {
 public:
  Cutter(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology) : mesh_(mesh), topology_(topology) {
    const std::size_t nf = mesh.triangles.size();
    core::Box3 box;
    for (const Vec3& v : mesh.vertices) box.add(v);
    const Vec3 size = box.max - box.min;
    const double scale = 1023.0 / std::max({size.x, size.y, size.z, 1e-9});
    auto spread = [](std::uint64_t x) {  // 10 bits to every third of 30
      x &= 0x3ff;
      x = (x | (x << 16)) & 0x30000ff;
      x = (x | (x << 8)) & 0x300f00f;
      x = (x | (x << 4)) & 0x30c30c3;
      return (x | (x << 2)) & 0x9249249;
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
      const auto& t = mesh.triangles[f];
      const Vec3 c = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0 - box.min;
      keyed[f] = {spread(static_cast<std::uint64_t>(c.x * scale)) | spread(static_cast<std::uint64_t>(c.y * scale)) << 1 |
                      spread(static_cast<std::uint64_t>(c.z * scale)) << 2,
                  f};
    }
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < nf; i += kClusterFaces) {
      Cluster c;
      c.first = static_cast<std::uint32_t>(order_.size());
      core::Box3 b;
      for (std::size_t j = i; j < std::min(nf, i + kClusterFaces); ++j) {
        order_.push_back(keyed[j].second);
        for (const std::uint32_t v : mesh.triangles[keyed[j].second]) b.add(mesh.vertices[v]);
      }
      c.count = static_cast<std::uint32_t>(order_.size()) - c.first;
      c.centre = (b.min + b.max) * 0.5;
      c.radius = 0.5 * core::norm(b.max - b.min);
      clusters_.push_back(c);
    }
  }

  // The section by {p : p·n = h}. With NEAR (the section below), only its islands that come within
  // REACH_MM of NEAR seen along n are kept: a plane turned with a curved branch passes through the
  // far parts of the mesh too (the next turn of a helix), which later planes build.
  Cut cut(Vec3 n, double h, const Cut* near = nullptr, double reach_mm = 0.0) {
    Cut c;
    c.frame = plane_frame(n, h);
    c.h = h;
    const SectionContext ctx(mesh_, c.frame.d, &topology_);
    faces_.clear();
    for (const Cluster& cl : clusters_) {
      if (std::fabs(core::dot(cl.centre, c.frame.d) - h) > cl.radius) continue;
      for (std::uint32_t i = cl.first; i < cl.first + cl.count; ++i) {
        const std::uint32_t f = order_[i];
        if (ctx.face_min(f) <= h && ctx.face_max(f) >= h) faces_.push_back(f);
      }
    }
    std::sort(faces_.begin(), faces_.end());  // face order: the same section whatever the clusters
    c.s = section(ctx, h, c.frame, faces_, scratch_);
    if (near != nullptr && c.s.polygons.size() > 1) keep_near(c, *near, reach_mm);
    const geom2d::Centroid g = geom2d::centroid(c.s.polygons);
    c.centroid = c.frame.to_world(g.x, g.y);
    for (const geom2d::Ring& r : geom2d::rings_of(c.s.polygons)) {
      for (const geom2d::Point& q : r) c.corners.push_back(c.frame.to_world(geom2d::to_mm(q.x), geom2d::to_mm(q.y)));
    }
    return c;
  }

 private:
  // An island is kept when it overlaps the section below grown by REACH_MM. The growth (an offset,
  // the costly part) is made only for islands that neither lie beyond its box nor have a corner
  // strictly inside the section below (then it overlaps it).
  static void keep_near(Cut& c, const Cut& near, double reach_mm) {
    const std::vector<geom2d::Polygon> under = project(near.s.polygons, near.frame, c.frame);
    Box2 grown = box_of(under);
    const std::int64_t margin = geom2d::to_units(reach_mm) + kBoxSlackUnits;
    grown.x0 -= margin, grown.y0 -= margin, grown.x1 += margin, grown.y1 += margin;
    std::optional<std::vector<geom2d::Ring>> zone;
    std::vector<geom2d::Polygon> kept;
    for (geom2d::Polygon& p : c.s.polygons) {
      if (!grown.meets(box_of({p}))) continue;
      bool overlaps = std::any_of(p.outer.begin(), p.outer.end(), [&](geom2d::Point q) { return strictly_inside(q, under); });
      if (!overlaps) {
        if (!zone) zone = geom2d::rings_of(geom2d::offset(under, reach_mm));
        overlaps = geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of({p}), *zone)) < geom2d::area_mm2(p);
      }
      if (overlaps) kept.push_back(std::move(p));
    }
    c.s.polygons = std::move(kept);
    c.s.area_mm2 = geom2d::area_mm2(c.s.polygons);
  }

  // Integer bounds of a set of polygons' outer rings.
  struct Box2 {
    std::int64_t x0 = INT64_MAX, y0 = INT64_MAX, x1 = INT64_MIN, y1 = INT64_MIN;
    bool meets(const Box2& o) const { return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1; }
  };
  static Box2 box_of(const std::vector<geom2d::Polygon>& polygons) {
    Box2 b;
    for (const geom2d::Polygon& p : polygons) {
      for (const geom2d::Point& q : p.outer) b.x0 = std::min(b.x0, q.x), b.y0 = std::min(b.y0, q.y), b.x1 = std::max(b.x1, q.x), b.y1 = std::max(b.y1, q.y);
    }
    return b;
  }
  // The offset's arcs are approximated inside its true outline; this covers its rounding.
  static constexpr std::int64_t kBoxSlackUnits = 1000;

  // -1 on an edge of RING, else 1 strictly inside it, 0 outside (exact).
  static int where(geom2d::Point p, const geom2d::Ring& ring) {
    bool in = false;
    for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
      const geom2d::Point a = ring[i], b = ring[(i + 1) % n];
      const int o = geom2d::orientation(a, b, p);
      if (o == 0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y)) return -1;
      if ((a.y > p.y) != (b.y > p.y) && (o > 0) == (b.y > a.y)) in = !in;
    }
    return in ? 1 : 0;
  }
  // P strictly inside one of POLYGONS (inside its outer ring, outside and off its holes).
  static bool strictly_inside(geom2d::Point p, const std::vector<geom2d::Polygon>& polygons) {
    return std::any_of(polygons.begin(), polygons.end(), [&](const geom2d::Polygon& poly) {
      return where(p, poly.outer) == 1 && std::none_of(poly.holes.begin(), poly.holes.end(), [&](const geom2d::Ring& h) { return where(p, h) != 0; });
    });
  }

  static constexpr std::size_t kClusterFaces = 32;
  struct Cluster {
    Vec3 centre;
    double radius = 0.0;
    std::uint32_t first = 0, count = 0;
  };
  const mesh::Mesh& mesh_;
  const mesh::EdgeTopology& topology_;
  std::vector<std::uint32_t> order_;  // faces in cluster order
  std::vector<Cluster> clusters_;
  std::vector<std::uint32_t> faces_;
  SectionScratch scratch_;
};

struct Verdict {
  bool ok = false;
  bool shaped = false;  // the thickness and the order of the planes hold (VolDiff or the overhang may not)
  double t_min = 0.0, t_max = 0.0;
};

// The tests of the file comment for the plane UPPER over the section BELOW.
Verdict judge(const Cut& below, const Cut& upper, const SliceOptions& o) {
  Verdict v;
  if (upper.empty()) return v;
  const Vec3 n = below.frame.d, d = upper.frame.d;
  const double cos_turn = core::dot(n, d);
  if (cos_turn <= 0.0) return v;
  v.t_min = INFINITY, v.t_max = -INFINITY;
  for (const Vec3& p : upper.corners) {
    const double t = (core::dot(p, n) - below.h) / cos_turn;
    v.t_min = std::min(v.t_min, t), v.t_max = std::max(v.t_max, t);
  }
  if (v.t_min < o.min_mm - kThicknessSlackMm || v.t_max > o.max_mm + kThicknessSlackMm) return v;
  for (const Vec3& q : below.corners) {
    if (core::dot(q, d) - upper.h > -kUnderShare * o.min_mm) return v;
  }
  v.shaped = true;
  if (!o.limits.voldiff && !o.limits.overhang_deg) return v.ok = true, v;
  const std::vector<geom2d::Polygon> under = project(below.s.polygons, below.frame, upper.frame);
  if (o.limits.voldiff) {
    const double denom = std::max(geom2d::area_mm2(under), upper.s.area_mm2);
    const auto band = geom2d::xor_rings(geom2d::rings_of(under), geom2d::rings_of(upper.s.polygons));
    if (denom > 0.0 && geom2d::area_mm2(band) / denom > *o.limits.voldiff) return v;
  }
  if (o.limits.overhang_deg) {
    const double grow = std::max(v.t_min * std::tan(*o.limits.overhang_deg * kPi / 180.0), o.limits.overhang_step_mm.value_or(0.0));
    const auto beyond = geom2d::difference_rings(geom2d::rings_of(upper.s.polygons), geom2d::rings_of(geom2d::offset(under, grow)));
    if (geom2d::area_mm2(beyond) > kOverhangAreaMm2) return v;
  }
  v.ok = true;
  return v;
}

double angle_deg(Vec3 a, Vec3 b) { return std::acos(std::clamp(core::dot(a, b), -1.0, 1.0)) * 180.0 / kPi; }

Layer layer_of(Cut&& c, double on_axis_mm, double t_min, double t_max, bool tilted) {
  Layer l;
  l.frame = c.frame;
  l.height_mm = c.h;
  l.below_mm = l.above_mm = on_axis_mm / 2.0;
  if (tilted) l.min_thickness_mm = t_min, l.max_thickness_mm = t_max;
  l.area_mm2 = c.s.area_mm2;
  l.polygons = std::move(c.s.polygons);
  return l;
}

// How far from the section below an island of the next one may lie and still grow from it: a
// layer's own thickness twice over plus the step a tilted torch may take.
double near_reach_mm(const SliceOptions& o) { return 2.0 * (o.max_mm + o.limits.overhang_step_mm.value_or(0.0)); }

// The plane at turn S ∈ [0, 1] from N towards the link L, through the axis point Δ on.
Cut turned(Cutter& cutter, const Cut& below, Vec3 n, Vec3 link, double s, double step, double reach_mm) {
  const Vec3 d = core::normalized(n + (link - n) * s);
  return cutter.cut(d, core::dot(below.centroid + d * step, d), &below, reach_mm);
}

struct Candidate {
  Cut cut;
  Verdict verdict;
  double turn = 0.0;  // the share of the link's turn taken
};

// The next plane over BELOW (file comment), or none where the part ends. At each step Δ the turn
// is halved from the whole link (Ruan's steps 1–2) until a plane passes, then bisected back up
// between the passing turn and the failing one (kRefine times): the largest turn found. The plane
// taking the whole link ends the search; otherwise the steps are tried down to ΔL_min and the one
// that follows the axis furthest is kept (the thicker on a tie).
std::optional<Candidate> next_plane(Cutter& cutter, const Cut& below, const SliceOptions& o, std::uint32_t& violations) {
  constexpr int kRefine = 4;
  const Vec3 n = below.frame.d;
  std::optional<Candidate> best, shaped;  // shaped: the furthest turn keeping only the thickness and the order
  auto keep_shaped = [&](const Cut& trial, const Verdict& v, double s) {
    if (v.shaped && (!shaped || s > shaped->turn)) shaped = Candidate{trial, v, s};
  };
  // The steps: the nominal one, then the middle of the range (the most room for the planes to turn:
  // a nominal step near an end of the range leaves them little), then Ruan's Δ − Δ/4 down to ΔL_min.
  const double nominal = std::clamp(o.layer_mm, o.min_mm, o.max_mm), middle = 0.5 * (o.min_mm + o.max_mm);
  std::vector<double> steps{nominal};
  if (std::fabs(middle - nominal) > kThicknessSlackMm) steps.push_back(middle);
  for (double step = nominal - kShrink * nominal; step >= o.min_mm - kThicknessSlackMm; step -= kShrink * step) steps.push_back(step);
  for (const double step : steps) {
    const Cut probe = cutter.cut(n, below.h + step, &below, near_reach_mm(o));
    if (probe.empty()) continue;
    const Vec3 to_probe = probe.centroid - below.centroid;
    const Vec3 link = core::dot(to_probe, n) > 0.0 ? core::normalized(to_probe) : n;
    std::optional<Candidate> here;
    // On the plane through c + D·Δ, the point over a corner q of the section below is (c − q)·D + Δ
    // thick, and (c − q)·D grows about linearly with the turn s: start from the turn that keeps
    // the corners below in range (the section above is much like them), not from the whole link.
    double spread = 0.0;
    for (const Vec3& q : below.corners) spread = std::max(spread, std::fabs(core::dot(below.centroid - q, link - n)));
    const double slack = std::min(o.max_mm - step, step - o.min_mm);
    const double start = spread * 1.0 > slack && spread > 0.0 ? std::max(slack, 0.0) / spread : 1.0;
    double fail = start < 1.0 ? std::min(1.0, 2.0 * start) : 0.0;  // a turn above the passing one to bisect towards
    // The same for the thickness and the order alone (the fallback when no plane passes).
    double shaped_at = -1.0, unshaped = fail;
    for (double s = start;; s *= 0.5) {
      Cut trial = turned(cutter, below, n, link, s, step, near_reach_mm(o));
      const Verdict v = judge(below, trial, o);
      if (v.ok) {
        here = Candidate{std::move(trial), v, s};
        break;
      }
      if (shaped_at < 0.0) (v.shaped ? shaped_at : unshaped) = s;
      keep_shaped(trial, v, s);
      fail = s;
      if (angle_deg(core::normalized(n + (link - n) * s), n) < kEpsDeg) break;
    }
    if (!here) {
      // The turn as far as the thickness and the order allow, bisected as a passing one would be
      // (judged on those alone: the limits failed at every smaller turn).
      SliceOptions shape_only = o;
      shape_only.limits.voldiff.reset(), shape_only.limits.overhang_deg.reset();
      for (int i = 0; i < kRefine && shaped_at >= 0.0 && unshaped > shaped_at; ++i) {
        const double mid = 0.5 * (shaped_at + unshaped);
        const Cut trial = turned(cutter, below, n, link, mid, step, near_reach_mm(o));
        const Verdict v = judge(below, trial, shape_only);
        keep_shaped(trial, v, mid);
        (v.shaped ? shaped_at : unshaped) = mid;
      }
      continue;
    }
    for (int i = 0; i < kRefine && fail > 0.0; ++i) {
      const double mid = 0.5 * (here->turn + fail);
      Cut trial = turned(cutter, below, n, link, mid, step, near_reach_mm(o));
      const Verdict v = judge(below, trial, o);
      if (v.ok) here = Candidate{std::move(trial), v, mid};
      else keep_shaped(trial, v, mid), fail = mid;
    }
    if (!best || here->turn > best->turn) best = std::move(here);
    if (best->turn == 1.0) break;
  }
  if (best) return best;
  // No plane meets every limit: the one turned furthest towards the axis with its thickness in
  // range (VolDiff and the overhang are given up for this layer, and the next ones can turn
  // further), else the plane parallel to the previous one at ΔL_min.
  if (shaped && shaped->turn > 0.0) {
    ++violations;
    shaped->verdict.ok = true;
    return shaped;
  }
  Cut flat = cutter.cut(n, below.h + o.min_mm, &below, near_reach_mm(o));
  if (flat.empty()) return std::nullopt;
  ++violations;
  return Candidate{std::move(flat), Verdict{true, true, o.min_mm, o.min_mm}, 0.0};
}

}  // namespace

core::Result<SliceResult> slice_tilted(const mesh::Mesh& mesh, const SliceOptions& o, const mesh::EdgeTopology* topology) {
  const mesh::EdgeTopology own = topology ? mesh::EdgeTopology{} : mesh::build_topology(mesh);
  Cutter cutter(mesh, topology ? *topology : own);
  const Vec3 d0 = core::normalized(o.direction);
  core::Box3 box;
  for (const Vec3& v : mesh.vertices) box.add(v);
  // Each layer goes at least ΔL_min/2 past every corner of the one below: a bound on the count.
  const double diagonal = core::norm(box.max - box.min);
  const auto max_layers = static_cast<std::size_t>(std::ceil(kPi * diagonal / (kUnderShare * o.min_mm))) + 16;
  double low = INFINITY, high = -INFINITY;
  for (const Vec3& v : mesh.vertices) low = std::min(low, core::dot(v, d0)), high = std::max(high, core::dot(v, d0));
  // The nominal step, but no thicker than the part along the first direction (a plate thinner
  // than a layer is one layer of its own thickness).
  const double t0 = std::clamp(std::min(o.layer_mm, high - low), o.min_mm, o.max_mm);
  SliceResult result;
  core::Progress progress("slicing (tilted)", 0);
  // The first layer: planar, half a layer above the lowest point (higher where that is empty:
  // a part starting at a point or an edge).
  std::optional<Cut> below;
  for (double h = low + t0 / 2.0; h < low + diagonal + t0; h += o.min_mm) {
    Cut c = cutter.cut(d0, h);
    if (!c.empty()) {
      below = std::move(c);
      break;
    }
  }
  if (!below) return result;
  result.layers.push_back(layer_of(Cut(*below), t0, t0, t0, false));
  double given_up_mm2 = 0.0;  // overhang of the layers that gave up a limit (give_up_overhang_mm2)
  while (result.layers.size() < max_layers) {
    const std::uint32_t violations = result.limit_violations;
    auto next = next_plane(cutter, *below, o, result.limit_violations);
    if (!next) break;
    if (o.give_up_overhang_mm2 && o.limits.overhang_deg && result.limit_violations > violations) {
      const double grow = std::max(next->verdict.t_min * std::tan(*o.limits.overhang_deg * kPi / 180.0), o.limits.overhang_step_mm.value_or(0.0));
      const auto under = geom2d::offset(project(below->s.polygons, below->frame, next->cut.frame), grow);
      given_up_mm2 += geom2d::area_mm2(geom2d::difference_rings(geom2d::rings_of(next->cut.s.polygons), geom2d::rings_of(under)));
      if (given_up_mm2 > *o.give_up_overhang_mm2) {
        return core::make_error(core::ErrorCode::kInfeasible,
                                fmt::format("tilted layers leave more than {:.1f} mm2 of overhang by layer {}", *o.give_up_overhang_mm2,
                                            result.layers.size()));
      }
    }
    const Vec3 axis_point = below->centroid;
    Cut& c = next->cut;
    // The thickness on the axis: from the previous centroid along the new normal to the plane.
    const double on_axis = (c.h - core::dot(axis_point, c.frame.d));
    const bool tilted = angle_deg(c.frame.d, below->frame.d) > 1e-9;
    Cut kept = c;
    result.layers.push_back(layer_of(std::move(c), on_axis, next->verdict.t_min, next->verdict.t_max, tilted));
    below = std::move(kept);
    progress.update(result.layers.size());
  }
  if (result.layers.size() >= max_layers) {
    return core::make_error(core::ErrorCode::kInternal,
                            fmt::format("tilted slicing: more than {} layers over a part {:.1f} mm across", max_layers, diagonal));
  }
  for (std::size_t k = 0; k < result.layers.size(); ++k) {
    Layer& l = result.layers[k];
    l.index = static_cast<std::uint32_t>(k);
    result.total_area_mm2 += l.area_mm2;
    result.volume_estimate_mm3 += l.area_mm2 * l.thickness_mm();
  }
  // Planes that cannot turn as fast as the part (a thin tube leaning far from the first layer)
  // wander off it and leave it partly unbuilt: refused rather than returned.
  const double volume = std::fabs(mesh::signed_volume(mesh));
  if (result.volume_estimate_mm3 < kCoveredShare * volume) {
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("tilted layers cover {:.0f} % of the part's volume ({:.1f} of {:.1f} mm3; {} of {} layers gave up a "
                                        "limit): the planes cannot turn with it within the thickness range",
                                        100.0 * result.volume_estimate_mm3 / volume, result.volume_estimate_mm3, volume,
                                        result.limit_violations, result.layers.size()));
  }
  return result;
}

}  // namespace polyaxis::slicing::detail
