#include "split_screen.h"

#include <algorithm>
#include <cmath>

#include "region_geometry.h"

namespace polyaxis::analysis::detail {
namespace {

// A vertex within this of the cut plane is on it, mm (the same as a facet resting on a base).
constexpr double kOnPlaneMm = kOnBaseMm;
// The direction search aims this far inside the self-supporting limit, degrees.
constexpr double kDirectionMarginDeg = 2.0;
// Pattern search: first and last step, degrees, and the cap on moves.
constexpr double kSearchStartDeg = 16.0;
// A candidate's child direction is only estimated while screening, to this step, degrees.
constexpr double kScreenSearchEndDeg = 2.0;
constexpr int kMaxSearchMoves = 200;

double depth_of(std::span<const FacetSample> facets, Vec3 d, double alpha_deg) {
  const double limit = -std::sin(alpha_deg * kPi / 180.0);
  double depth = 0.0;
  for (const FacetSample& f : facets) depth += f.area_mm2 * std::max(0.0, limit - core::dot(f.normal, d));
  return depth;
}

// Screening sums the child's facets into at most 6·kNormalBins² normal bins (cube map), each with
// its area-weighted mean normal, once it has more facets than that: the overhang depends only on
// normals and areas, and the bins keep the direction search O(bins) on large meshes.
constexpr int kNormalBins = 24;

std::vector<FacetSample> binned(const std::vector<FacetSample>& facets) {
  constexpr std::size_t kBins = 6 * kNormalBins * kNormalBins;
  if (facets.size() <= kBins) return facets;
  std::vector<Vec3> sum(kBins);
  std::vector<double> area(kBins, 0.0);
  for (const FacetSample& f : facets) {
    const Vec3 n = f.normal;
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    int face = 0;
    double u = 0.0, v = 0.0, m = 0.0;
    if (ax >= ay && ax >= az) face = n.x > 0 ? 0 : 1, u = n.y, v = n.z, m = ax;
    else if (ay >= az) face = n.y > 0 ? 2 : 3, u = n.x, v = n.z, m = ay;
    else face = n.z > 0 ? 4 : 5, u = n.x, v = n.y, m = az;
    auto cell = [](double t) { return std::clamp(static_cast<int>((t + 1.0) / 2.0 * kNormalBins), 0, kNormalBins - 1); };
    const auto b = static_cast<std::size_t>((face * kNormalBins + cell(u / m)) * kNormalBins + cell(v / m));
    sum[b] = sum[b] + n * f.area_mm2;
    area[b] += f.area_mm2;
  }
  std::vector<FacetSample> out;
  for (std::size_t b = 0; b < kBins; ++b) {
    if (area[b] > 0.0) out.push_back({core::normalized(sum[b]), area[b]});
  }
  return out;
}

Vec3 any_perpendicular(Vec3 v) {
  const Vec3 a = std::fabs(v.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return core::normalized(core::cross(v, a));
}

// Area of the part of triangle ABC where the signed distances S are >= 0, mm².
double positive_area(const Vec3 (&p)[3], const double (&s)[3], Vec3 unit_normal) {
  Vec3 poly[4];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    if (s[k] >= 0.0) poly[n++] = p[k];
    if ((s[k] > 0.0 && s[j] < 0.0) || (s[k] < 0.0 && s[j] > 0.0)) poly[n++] = p[k] + (p[j] - p[k]) * (s[k] / (s[k] - s[j]));
  }
  Vec3 area{};
  for (int k = 1; k + 1 < n; ++k) area = area + core::cross(poly[k] - poly[0], poly[k + 1] - poly[0]);
  return std::max(0.0, core::dot(area, unit_normal) / 2.0);
}

}  // namespace

Vec3 DirectionCone::nearest(Vec3 unit) const {
  if (admits(unit)) return unit;
  const Vec3 a = core::normalized(axis);
  const Vec3 side = unit - a * core::dot(unit, a);
  const Vec3 across = core::norm(side) > 1e-12 ? core::normalized(side) : any_perpendicular(a);
  const double c = std::clamp(min_cos, -1.0, 1.0);
  return core::normalized(a * c + across * std::sqrt(std::max(0.0, 1.0 - c * c)));
}

std::vector<FacetSample> facet_samples(const mesh::Mesh& m, Vec3 base_point, Vec3 base_normal) {
  std::vector<FacetSample> out;
  out.reserve(m.triangles.size());
  const Vec3 bn = core::normalized(base_normal);
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const Vec3 a2 = mesh::face_area_vector(m, f);
    const double len = core::norm(a2);
    if (len == 0.0) continue;
    bool on_base = true;
    for (int k = 0; k < 3; ++k) on_base = on_base && std::fabs(core::dot(m.corner(f, k) - base_point, bn)) <= kOnBaseMm;
    if (!on_base) out.push_back({a2 / len, len / 2.0});
  }
  return out;
}

double overhang_of(std::span<const FacetSample> facets, Vec3 d, double alpha_deg) {
  const double limit = -std::sin(alpha_deg * kPi / 180.0);
  double area = 0.0;
  for (const FacetSample& f : facets) area += core::dot(f.normal, d) < limit ? f.area_mm2 : 0.0;
  return area;
}

Vec3 best_direction(std::span<const FacetSample> facets, Vec3 base_normal, std::span<const Vec3> starts, double alpha_deg,
                    double finest_step_deg, const DirectionCone& reach) {
  const Vec3 bn = core::normalized(base_normal);
  const Vec3 first = reach.nearest(bn);
  const double strict = alpha_deg - kDirectionMarginDeg;
  const double min_cos = std::cos(max_base_tilt_deg(alpha_deg) * kPi / 180.0);
  Vec3 best = first;
  double best_depth = depth_of(facets, first, strict);
  for (Vec3 s : starts) {
    s = core::normalized(s);
    if (core::dot(s, bn) < min_cos - 1e-12 || !reach.admits(s)) continue;
    const double d = depth_of(facets, s, strict);
    if (d < best_depth) best = s, best_depth = d;
  }
  const Vec3 best_start = best;
  int moves = 0;
  for (double step = kSearchStartDeg; step >= finest_step_deg && best_depth > 0.0 && moves < kMaxSearchMoves; step /= 2.0) {
    bool moved = true;
    while (moved && best_depth > 0.0 && moves < kMaxSearchMoves) {
      moved = false;
      const Vec3 u = any_perpendicular(best), v = core::cross(best, u);
      const double c = std::cos(step * kPi / 180.0), s = std::sin(step * kPi / 180.0);
      for (int k = 0; k < 8; ++k) {
        const double phi = k * kPi / 4.0;
        const Vec3 probe = core::normalized(best * c + (u * std::cos(phi) + v * std::sin(phi)) * s);
        if (core::dot(probe, bn) < min_cos || !reach.admits(probe)) continue;
        const double d = depth_of(facets, probe, strict);
        if (d < best_depth) {
          best = probe, best_depth = d, moved = true;
          ++moves;
          break;
        }
      }
    }
  }
  // A probe within the margin may still leave facets past the true limit (the depth is a sum): keep
  // the best start instead when it overhangs less at the real angle.
  return overhang_of(facets, best_start, alpha_deg) < overhang_of(facets, best, alpha_deg) ? best_start : best;
}

std::vector<std::uint32_t> nearest_facets(const mesh::Mesh& m, std::span<const Vec3> targets) {
  std::vector<std::uint32_t> out;
  for (const Vec3& t : targets) {
    double best = INFINITY;
    std::uint32_t pick = 0;
    for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
      const double d2 = distance2_to_triangle(t, m.corner(f, 0), m.corner(f, 1), m.corner(f, 2));
      if (d2 < best) best = d2, pick = f;
    }
    if (best < INFINITY) out.push_back(pick);
  }
  return out;
}

HostFaces host_faces(const mesh::Mesh& m, Vec3 direction, Vec3 base_point, Vec3 base_normal, double alpha_deg) {
  const std::size_t nf = m.triangles.size();
  const double limit = -std::sin(alpha_deg * kPi / 180.0);
  const Vec3 hd = core::normalized(direction), hb = core::normalized(base_normal);
  HostFaces out;
  out.normal.resize(nf), out.area_mm2.assign(nf, 0.0), out.on_base.assign(nf, 0), out.overhangs.assign(nf, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec3 a2 = mesh::face_area_vector(m, f);
    const double len = core::norm(a2);
    if (len == 0.0) continue;
    const Vec3 n = a2 / len;
    bool on_base = true;
    for (int k = 0; k < 3; ++k) on_base = on_base && std::fabs(core::dot(m.corner(f, k) - base_point, hb)) <= kOnBaseMm;
    out.normal[f] = n, out.area_mm2[f] = len / 2.0, out.on_base[f] = on_base;
    out.overhangs[f] = !on_base && core::dot(n, hd) < limit;
    out.area_sum_mm2 += len / 2.0;
    out.volume_mm3 += core::dot(m.corner(f, 0), n) * len / 6.0;
    if (out.overhangs[f]) out.overhang_sum_mm2 += len / 2.0;
  }
  return out;
}

Screened screen_split(const HostRegion& host, Vec3 point, Vec3 normal, std::span<const std::uint32_t> seeds,
                      std::span<const Vec3> direction_starts, double alpha_deg) {
  Screened out;
  const mesh::Mesh& m = *host.mesh;
  const std::size_t nv = m.vertices.size(), nf = m.triangles.size();
  const HostFaces own = host.faces ? HostFaces{} : host_faces(m, host.direction, host.base_point, host.base_normal, alpha_deg);
  const HostFaces& hf = host.faces ? *host.faces : own;
  // Signed distances of the corners the search reaches, and the facets reached, stamped per call
  // (each thread keeps its own arrays: a call visits the child's facets only).
  thread_local std::vector<double> tl_s;
  thread_local std::vector<std::uint32_t> tl_s_stamp, tl_reached_stamp;
  thread_local std::uint32_t tl_epoch = 0;
  if (tl_s.size() < nv) tl_s.resize(nv), tl_s_stamp.resize(nv, 0);
  if (tl_reached_stamp.size() < nf) tl_reached_stamp.resize(nf, 0);
  if (++tl_epoch == 0) std::fill(tl_s_stamp.begin(), tl_s_stamp.end(), 0), std::fill(tl_reached_stamp.begin(), tl_reached_stamp.end(), 0), tl_epoch = 1;
  // Plain pointers from here: the thread's storage is looked up once, not at every access.
  double* const s = tl_s.data();
  std::uint32_t* const s_stamp = tl_s_stamp.data();
  std::uint32_t* const reached_stamp = tl_reached_stamp.data();
  const std::uint32_t epoch = tl_epoch;
  const Vec3* const vertices = m.vertices.data();
  const auto* const triangles = m.triangles.data();
  const std::uint32_t* const opposite = host.topology->opposite.data();
  auto dist = [&](std::uint32_t v) {
    if (s_stamp[v] != epoch) {
      const double d = core::dot(vertices[v] - point, normal);
      s[v] = std::fabs(d) <= kOnPlaneMm ? 0.0 : d, s_stamp[v] = epoch;
    }
    return s[v];
  };
  auto touches = [&](std::size_t f) { return dist(triangles[f][0]) > 0.0 || dist(triangles[f][1]) > 0.0 || dist(triangles[f][2]) > 0.0; };
  std::vector<std::uint32_t> stack, reached;
  for (const std::uint32_t f : seeds) {
    if (reached_stamp[f] != epoch && touches(f)) reached_stamp[f] = epoch, stack.push_back(f), reached.push_back(f);
  }
  if (stack.empty()) return out;
  while (!stack.empty()) {
    const std::uint32_t f = stack.back();
    stack.pop_back();
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t o = opposite[3 * f + k];
      if (o == mesh::kNoHalfEdge) continue;
      const std::uint32_t g = o / 3;
      if (reached_stamp[g] == epoch || !touches(g)) continue;
      if (std::max(dist(triangles[f][k]), dist(triangles[f][(k + 1) % 3])) <= 0.0) continue;  // the edge is not on the child side
      reached_stamp[g] = epoch;
      stack.push_back(g), reached.push_back(g);
    }
  }
  // In the search's order (deterministic: the seeds' and the topology's).
  std::vector<FacetSample> child;
  child.reserve(reached.size());
  double child_cap_mm2 = 0.0, child_area = 0.0, child_overhang = 0.0;
  double child_volume = 0.0;  // about POINT: the cap, in the plane, adds nothing
  for (const std::uint32_t f : reached) {
    if (hf.area_mm2[f] == 0.0) continue;
    const Vec3 n = hf.normal[f];
    const double sv[3] = {dist(triangles[f][0]), dist(triangles[f][1]), dist(triangles[f][2])};
    double in_child = hf.area_mm2[f];  // whole on the child side, else clipped at the plane
    if (sv[0] <= 0.0 || sv[1] <= 0.0 || sv[2] <= 0.0) {
      const Vec3 p[3] = {m.corner(f, 0), m.corner(f, 1), m.corner(f, 2)};
      in_child = std::min(in_child, positive_area(p, sv, n));
    }
    if (in_child > 0.0 && hf.on_base[f] && host.keep_base) return out;
    if (in_child > 0.0) child.push_back({n, in_child}), out.child_area_mm2 += in_child;
    child_cap_mm2 += in_child * core::dot(n, normal);
    child_volume += in_child * core::dot(m.corner(f, 0) - point, n) / 3.0;  // the same at every point of the facet's plane
    child_area += in_child;
    if (hf.overhangs[f]) child_overhang += in_child;
  }
  // The parent keeps every facet's part off the child: the host's sums less the child's.
  const double parent_area = hf.area_sum_mm2 - child_area;
  out.parent_mm2 = std::max(0.0, hf.overhang_sum_mm2 - child_overhang);
  if (child.empty() || parent_area <= kUnsupportedNoiseMm2) return out;
  // Either piece thinner on average than a region can be laid (a film, a sliver): no split.
  const double cap = std::max(0.0, child_cap_mm2), min_t = host.min_thickness_mm;
  if (2.0 * child_volume < min_t * (child_area + cap) || 2.0 * (hf.volume_mm3 - child_volume) < min_t * (parent_area + cap)) return out;
  const double limit = -std::sin(alpha_deg * kPi / 180.0);
  const Vec3 hd = core::normalized(host.direction), hb = core::normalized(host.base_normal);
  // The cap closes both pieces; the parent's copy faces the child (+NORMAL). It rests on nothing
  // while the parent is built unless it lies on the parent's own base.
  const bool cap_on_base = std::fabs(core::dot(normal, hb)) > 1.0 - 1e-9 && std::fabs(core::dot(point - host.base_point, hb)) <= kOnBaseMm;
  if (!cap_on_base && core::dot(normal, hd) < limit) out.parent_mm2 += std::max(0.0, child_cap_mm2);
  const std::vector<FacetSample> bins = binned(child);
  out.child_direction = best_direction(bins, normal, direction_starts, alpha_deg, kScreenSearchEndDeg, host.reach);
  out.child_mm2 = overhang_of(child, out.child_direction, alpha_deg);
  if (const double on_cut = underside_in_cut_mm2(m, point, normal, host.min_thickness_mm); on_cut >= kUnsupportedNoiseMm2) out.child_mm2 += on_cut;
  out.valid = true;
  return out;
}

}  // namespace polyaxis::analysis::detail
