#include "region_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "polyaxis/core/tolerances.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::analysis::detail {
namespace {

// Facets whose unit normals differ by less than this (and share an edge) belong to one planar face.
constexpr double kCoplanarCos = 0.9999999;
// A neighbour's far corner this far above a face's plane makes the shared edge concave, mm, when
// the two meet at a crease: their normals at least kCreaseDeg apart. The facets of a tessellated
// curve (a bore's, 3.75° apart at 96 sides) meet at shallower steps that are not edges of the part.
constexpr double kConcaveRiseMm = 1e-9;
constexpr double kCreaseDeg = 20.0;
// Faces this far on the parent's side of a cut are in it (underside_in_cut_mm2), mm.
constexpr double kUndersideBandMm = 2.0 * kFaceCutOffsetMm;
// A face under a cut, within the least layer of it, that faces away from it within this angle
// bounds a film the cut leaves the parent, degrees (underside_in_cut_mm2).
constexpr double kFilmFacingDeg = 45.0;
// Corners within this of one another along a direction are level, mm: rounding of a cut's points on
// a plane across the direction. Level corners are ordered along kTieBreak, a direction no part's
// edges follow by design.
constexpr double kMinimumRiseMm = 1e-6;
constexpr Vec3 kTieBreak{0.5773502691896258, 0.5773397, 0.5773608};
// A lowest corner starts in mid-air when no point of the solid lies the probe distance below it,
// straight down or that far across in kMidAirProbes directions; at least this far, mm (far above
// a cut's film, kFaceCutOffsetMm, and rounding).
constexpr double kMinMidAirProbeMm = 0.05;
constexpr int kMidAirProbes = 8;
// Lowest corners probed at most, lowest first (each probe is O(F)).
constexpr std::size_t kMaxProbedStarts = 64;

}  // namespace

// Ericson, Real-Time Collision Detection §5.1.5 (closest point on a triangle).
double distance2_to_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = core::dot(ab, ap), d2 = core::dot(ac, ap);
  auto d2to = [&](Vec3 q) { return core::dot(p - q, p - q); };
  if (d1 <= 0.0 && d2 <= 0.0) return d2to(a);
  const Vec3 bp = p - b;
  const double d3 = core::dot(ab, bp), d4 = core::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return d2to(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return d2to(a + ab * (d1 / (d1 - d3)));
  const Vec3 cp = p - c;
  const double d5 = core::dot(ab, cp), d6 = core::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return d2to(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return d2to(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return d2to(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  return d2to(a + ab * (vb * denom) + ac * (vc * denom));
}

std::vector<PlanarFace> planar_faces(const mesh::Mesh& m) {
  const mesh::EdgeTopology topo = mesh::build_topology(m);
  const std::size_t nf = m.triangles.size();
  std::vector<Vec3> normal(nf);
  for (std::size_t f = 0; f < nf; ++f) normal[f] = core::normalized(mesh::face_area_vector(m, f));
  std::vector<std::uint32_t> face_of(nf, mesh::kNoHalfEdge);
  const double crease_cos = std::cos(kCreaseDeg * kPi / 180.0);
  std::vector<PlanarFace> faces;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < nf; ++seed) {
    if (face_of[seed] != mesh::kNoHalfEdge) continue;
    const auto id = static_cast<std::uint32_t>(faces.size());
    PlanarFace face{normal[seed], m.corner(seed, 0), 0.0, 0, false, {}};
    stack.assign(1, seed);
    face_of[seed] = id;
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      face.area_mm2 += core::norm(mesh::face_area_vector(m, f)) / 2.0;
      ++face.facets;
      face.facet_ids.push_back(f);
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t o = topo.opposite[3 * f + k];
        if (o == mesh::kNoHalfEdge) continue;
        const std::uint32_t g = o / 3;
        if (core::dot(normal[g], face.normal) >= kCoplanarCos) {
          if (face_of[g] == mesh::kNoHalfEdge) {
            face_of[g] = id;
            stack.push_back(g);
          }
          continue;
        }
        const Vec3 far = m.vertices[m.triangles[g][(o % 3 + 2) % 3]];
        if (core::dot(normal[g], face.normal) <= crease_cos && core::dot(far - face.point, face.normal) > kConcaveRiseMm) face.concave_edge = true;
      }
    }
    faces.push_back(std::move(face));
  }
  return faces;
}

double angle_deg(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)) * 180.0 / kPi;
}

double winding(const mesh::Mesh& m, Vec3 p) { return mesh::winding_number(m, p); }

double distance_to_solid(const mesh::Mesh& m, Vec3 p) {
  if (m.triangles.empty()) return INFINITY;
  // Outside the box of its vertices a point is outside the solid: the winding number (an arctangent
  // per facet) is worked out only inside it.
  core::Box3 box;
  for (const Vec3& v : m.vertices) box.add(v);
  const bool in_box = p.x >= box.min.x && p.x <= box.max.x && p.y >= box.min.y && p.y <= box.max.y && p.z >= box.min.z && p.z <= box.max.z;
  if (in_box && winding(m, p) > core::kInsideWindingNumber) return 0.0;
  double best = INFINITY;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) best = std::min(best, distance2_to_triangle(p, m.corner(f, 0), m.corner(f, 1), m.corner(f, 2)));
  return std::sqrt(best);
}

std::vector<OverhangPatch> overhang_patches(const mesh::Mesh& m, const mesh::EdgeTopology& topo, Vec3 d, double alpha_deg,
                                            Vec3 base_point, Vec3 base_normal) {
  const Vec3 dn = core::normalized(d), bn = core::normalized(base_normal);
  const double limit = -std::sin(alpha_deg * kPi / 180.0);
  const std::size_t nf = m.triangles.size();
  std::vector<double> area(nf, 0.0);  // > 0 for an overhanging facet
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec3 n2 = mesh::face_area_vector(m, f);
    const double len = core::norm(n2);
    if (len == 0.0 || core::dot(n2, dn) >= limit * len) continue;
    bool on_base = true;
    for (int k = 0; k < 3; ++k) on_base = on_base && std::fabs(core::dot(m.corner(f, k) - base_point, bn)) <= kOnBaseMm;
    if (!on_base) area[f] = len / 2.0;
  }
  // Patches of overhanging facets joined across edges; each counts only from the noise floor up.
  std::vector<char> seen(nf, 0);
  std::vector<OverhangPatch> out;
  for (std::uint32_t seed = 0; seed < nf; ++seed) {
    if (area[seed] <= 0.0 || seen[seed]) continue;
    OverhangPatch patch;
    seen[seed] = 1;
    patch.facets.assign(1, seed);
    for (std::size_t i = 0; i < patch.facets.size(); ++i) {
      const std::uint32_t f = patch.facets[i];
      patch.area_mm2 += area[f];
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t o = topo.opposite[3 * f + k];
        if (o == mesh::kNoHalfEdge || seen[o / 3] || area[o / 3] <= 0.0) continue;
        seen[o / 3] = 1;
        patch.facets.push_back(o / 3);
      }
    }
    if (patch.area_mm2 >= kUnsupportedNoiseMm2) out.push_back(std::move(patch));
  }
  std::stable_sort(out.begin(), out.end(), [](const OverhangPatch& a, const OverhangPatch& b) { return a.area_mm2 > b.area_mm2; });
  return out;
}

double unsupported(const mesh::Mesh& m, Vec3 d, double alpha_deg, Vec3 base_point, Vec3 base_normal) {
  double total = 0.0;
  for (const OverhangPatch& p : overhang_patches(m, mesh::build_topology(m), d, alpha_deg, base_point, base_normal)) total += p.area_mm2;
  return total;
}

double underside_in_cut_mm2(const mesh::Mesh& m, Vec3 point, Vec3 normal, double film_mm) {
  const Vec3 n = core::normalized(normal);
  const double band = std::max(kUndersideBandMm, film_mm), film_cos = std::cos(kFilmFacingDeg * std::numbers::pi / 180.0);
  double area = 0.0;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    // In the band first: one dot product turns most faces away (this runs once per screened split).
    bool in_cut = true, in_face_band = true;
    for (int k = 0; k < 3 && in_cut; ++k) {
      const double d = core::dot(m.corner(f, k) - point, n);
      in_cut = d <= kOnBaseMm && d >= -band;
      in_face_band = in_face_band && d >= -kUndersideBandMm;
    }
    if (!in_cut) continue;
    const Vec3 a2 = mesh::face_area_vector(m, f);
    const double len = core::norm(a2);
    if (len == 0.0) continue;
    const double facing = -core::dot(a2, n) / len;  // 1: facing straight away from the child
    if (in_face_band && facing >= kCoplanarCos) {
      area += len / 2.0;
    } else if (film_mm > 0.0 && facing >= film_cos) {
      area += facing * len / 2.0;  // a film's face, seen along the cut's normal
    }
  }
  return area;
}

std::vector<Vec3> mid_air_starts(const mesh::Mesh& m, Vec3 d, Vec3 base_point, Vec3 base_normal, double probe_mm) {
  const double probe = std::max(probe_mm, kMinMidAirProbeMm);
  const Vec3 dn = core::normalized(d), bn = core::normalized(base_normal);
  const std::size_t nv = m.vertices.size();
  std::vector<double> h(nv), across(nv);
  for (std::size_t v = 0; v < nv; ++v) h[v] = core::dot(m.vertices[v], dn), across[v] = core::dot(m.vertices[v], kTieBreak);
  // U is below V: lower along D, or level with it and lower along kTieBreak (a level keel or
  // plateau then has one lowest corner, as a surface tilted ever so slightly would).
  auto below = [&](std::uint32_t u, std::uint32_t v) {
    return h[u] < h[v] - kMinimumRiseMm || (h[u] <= h[v] + kMinimumRiseMm && across[u] < across[v]);
  };
  std::vector<char> lowest(nv, 1);
  std::vector<Vec3> normal(nv);
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const Vec3 a2 = mesh::face_area_vector(m, f);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = m.triangles[f][k];
      if (below(m.triangles[f][(k + 1) % 3], v) || below(m.triangles[f][(k + 2) % 3], v)) lowest[v] = 0;
      normal[v] = normal[v] + a2;
    }
  }
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!lowest[v] || !(core::dot(normal[v], dn) < 0.0)) continue;  // not a minimum, or the solid lies below it (a pocket's floor)
    if (std::fabs(core::dot(m.vertices[v] - base_point, bn)) <= kOnBaseMm) continue;
    candidates.push_back(v);
  }
  std::stable_sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) { return h[a] < h[b]; });
  if (candidates.size() > kMaxProbedStarts) candidates.resize(kMaxProbedStarts);
  // A corner lowest on the surface only: the solid reaches below it close by (the film a cut along
  // a face leaves on the parent, 1 µm proud of it, and the wedge a flat cut leaves along a curved
  // wall, have such corners along their lower edges).
  const Vec3 u = core::normalized(core::cross(dn, std::fabs(dn.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0})), w = core::cross(dn, u);
  auto solid_below = [&](Vec3 p) {
    const Vec3 under = p - dn * probe;
    if (winding(m, under) > core::kInsideWindingNumber) return true;
    for (int k = 0; k < kMidAirProbes; ++k) {
      const double a = 2.0 * kPi * k / kMidAirProbes;
      if (winding(m, under + (u * std::cos(a) + w * std::sin(a)) * probe) > core::kInsideWindingNumber) return true;
    }
    return false;
  };
  std::vector<Vec3> out;
  for (const std::uint32_t v : candidates) {
    if (!solid_below(m.vertices[v])) out.push_back(m.vertices[v]);
  }
  return out;
}

std::vector<mesh::Mesh> shells_of(const mesh::Mesh& piece) {
  std::vector<mesh::Mesh> out;
  if (piece.triangles.empty()) return out;
  mesh::RepairOptions o;
  o.check_self_intersections = false;
  o.max_hole_edges = 0;
  auto r = mesh::repair(io::RawMesh{piece.vertices, piece.triangles}, o);
  if (!r) return out;
  for (const mesh::Shell& s : r.value().shells) {
    mesh::Mesh m;
    m.vertices = r.value().mesh.vertices;
    m.triangles.assign(r.value().mesh.triangles.begin() + s.first_face, r.value().mesh.triangles.begin() + s.first_face + s.face_count);
    out.push_back(std::move(m));
  }
  return out;
}


}  // namespace polyaxis::analysis::detail
