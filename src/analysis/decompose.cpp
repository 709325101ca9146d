#include "polyaxis/analysis/decompose.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Facets whose unit normals differ by less than this (and share an edge) belong to one planar face.
constexpr double kCoplanarCos = 0.9999999;
// Unsupported area below this is the cut's own numerical noise.
constexpr double kUnsupportedNoiseMm2 = 0.01;
// A splitting face is a real planar face of the part, not one facet of a tessellated curve: it
// has at least this many facets and this much area. At most kMaxSplitCandidates faces, the nearest
// to the break link, are tried per link (each try is a CGAL cut).
constexpr std::uint32_t kMinSplitFaceFacets = 2;
constexpr double kMinSplitFaceMm2 = 1.0;
constexpr std::size_t kMaxSplitCandidates = 8;
// A facet within this of a region's base plane rests on it.
constexpr double kOnBaseMm = 1e-6;
// A face within this angle of facing straight down, and at least this large, is a candidate for
// the plate (the root's base).
constexpr double kPlateFaceDeg = 1.0;
constexpr double kMinPlateFaceMm2 = 1.0;
// A splitting plane within this of a link's extent still counts as overlapping it (Ruan Eq. 5).
constexpr double kLinkOverlapMm = 1e-6;

struct PlanarFace {
  Vec3 normal;
  Vec3 point;
  double area_mm2 = 0.0;
  std::uint32_t facets = 0;
  bool concave_edge = false;
};

// Planar faces of MESH (coplanar facets joined across edges), with whether their boundary has a
// concave edge (the neighbouring facet rises above the face's plane).
std::vector<PlanarFace> planar_faces(const mesh::Mesh& m) {
  const mesh::EdgeTopology topo = mesh::build_topology(m);
  const std::size_t nf = m.triangles.size();
  std::vector<Vec3> normal(nf);
  for (std::size_t f = 0; f < nf; ++f) normal[f] = core::normalized(mesh::face_area_vector(m, f));
  std::vector<std::uint32_t> face_of(nf, mesh::kNoHalfEdge);
  std::vector<PlanarFace> faces;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < nf; ++seed) {
    if (face_of[seed] != mesh::kNoHalfEdge) continue;
    const auto id = static_cast<std::uint32_t>(faces.size());
    PlanarFace face{normal[seed], m.corner(seed, 0), 0.0, 0, false};
    stack.assign(1, seed);
    face_of[seed] = id;
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      face.area_mm2 += core::norm(mesh::face_area_vector(m, f)) / 2.0;
      ++face.facets;
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
        // A boundary edge: concave when the neighbour's far corner lies above this face's plane.
        const Vec3 far = m.vertices[m.triangles[g][(o % 3 + 2) % 3]];
        if (core::dot(far - face.point, face.normal) > 1e-9) face.concave_edge = true;
      }
    }
    faces.push_back(face);
  }
  return faces;
}

double angle_deg(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)) * 180.0 / kPi;
}

// Generalised winding number of M at P: about 1 inside a closed outward mesh, 0 outside.
double winding(const mesh::Mesh& m, Vec3 p) {
  double omega = 0.0;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const Vec3 a = m.corner(f, 0) - p, b = m.corner(f, 1) - p, c = m.corner(f, 2) - p;
    const double la = core::norm(a), lb = core::norm(b), lc = core::norm(c);
    omega += 2.0 * std::atan2(core::dot(a, core::cross(b, c)),
                              la * lb * lc + core::dot(a, b) * lc + core::dot(a, c) * lb + core::dot(b, c) * la);
  }
  return omega / (4.0 * kPi);
}

// Overhang area of M built along D, not counting the facets lying on its base plane (BASE_POINT,
// BASE_NORMAL): they rest on the parent region or the plate. (mesh::overhang_area would count a
// base that is not perpendicular to D.)
double unsupported(const mesh::Mesh& m, Vec3 d, double alpha_deg, Vec3 base_point, Vec3 base_normal) {
  const Vec3 dn = core::normalized(d), bn = core::normalized(base_normal);
  const double limit = -std::sin(alpha_deg * kPi / 180.0);
  double area = 0.0;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const Vec3 n2 = mesh::face_area_vector(m, f);
    const double len = core::norm(n2);
    if (len == 0.0 || core::dot(n2, dn) >= limit * len) continue;
    bool on_base = true;
    for (int k = 0; k < 3; ++k) on_base = on_base && std::fabs(core::dot(m.corner(f, k) - base_point, bn)) <= kOnBaseMm;
    if (!on_base) area += len / 2.0;
  }
  return area < kUnsupportedNoiseMm2 ? 0.0 : area;
}

// The shells of a cut piece, as separate closed meshes (repair groups faces by shell).
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

mesh::Mesh merged(const std::vector<mesh::Mesh>& parts) {
  mesh::Mesh out;
  for (const mesh::Mesh& p : parts) {
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.insert(out.vertices.end(), p.vertices.begin(), p.vertices.end());
    for (auto t : p.triangles) out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return out;
}

struct Split {
  mesh::Mesh parent, child;
  Vec3 point, normal;  // the cut plane, normal pointing into the child
  Vec3 direction;      // the child's build direction
  double unsupported = INFINITY;
  std::string rule;
};

// Cuts REGION by the plane (POINT, NORMAL oriented towards TARGET); the child is the shell holding
// TARGET (or nearest to it), everything else stays with the parent.
std::optional<Split> try_split(const Region& region, Vec3 point, Vec3 normal, Vec3 target, Vec3 link_dir, double alpha,
                               const std::string& rule) {
  if (core::dot(target - point, normal) < 0.0) normal = normal * -1.0;
  auto cut = mesh::cut_by_plane(region.mesh, point, normal * -1.0);  // "below" = the child's side
  if (!cut) return std::nullopt;
  std::vector<mesh::Mesh> child_side = shells_of(cut.value().below);
  if (child_side.empty() || cut.value().above.triangles.empty()) return std::nullopt;
  std::size_t pick = 0;
  double best = -INFINITY;
  for (std::size_t i = 0; i < child_side.size(); ++i) {
    const double w = winding(child_side[i], target);
    if (w > best) best = w, pick = i;
  }
  Split s;
  s.child = std::move(child_side[pick]);
  std::vector<mesh::Mesh> rest{cut.value().above};
  for (std::size_t i = 0; i < child_side.size(); ++i) {
    if (i != pick) rest.push_back(child_side[i]);
  }
  s.parent = merged(rest);
  s.point = point;
  s.normal = normal;
  s.rule = rule;
  // The child grows from the cut: along the plane normal (Ruan §4.2.1: the reverse of the base
  // surface's normal), or along the link, whichever leaves less overhang.
  const double parent_overhang = unsupported(s.parent, region.build_direction, alpha, region.base_point, region.base_normal);
  const double along_normal = unsupported(s.child, normal, alpha, point, normal);
  const double along_link = core::dot(link_dir, normal) > 0.0 ? unsupported(s.child, link_dir, alpha, point, normal) : INFINITY;
  s.direction = along_link < along_normal ? core::normalized(link_dir) : normal;
  s.unsupported = parent_overhang + std::min(along_normal, along_link);
  return s;
}

}  // namespace

core::Result<RegionTree> decompose(const mesh::Mesh& mesh, const CentroidalAxis& axis, const DecomposeOptions& options) {
  RegionTree tree;
  Region root;
  root.id = 0;
  root.build_direction = core::normalized(options.root_direction);
  root.base_normal = root.build_direction;
  root.mesh = mesh;
  double lowest = INFINITY;
  for (const Vec3& v : mesh.vertices) lowest = std::min(lowest, core::dot(v, root.build_direction));
  root.base_point = root.build_direction * lowest;
  root.rule = "plate";
  const std::vector<PlanarFace> faces = planar_faces(mesh);
  // The plate: the lowest planar face looking straight down (the larger on a tie). What hangs
  // below it (knuckles under a body, a corner poking through a base plate) becomes regions built
  // downwards from it; with no such face the plate is at the lowest point.
  const PlanarFace* plate = nullptr;
  const Vec3 up = root.build_direction;
  for (const PlanarFace& f : faces) {
    if (f.area_mm2 < kMinPlateFaceMm2 || angle_deg(f.normal, up * -1.0) > kPlateFaceDeg) continue;
    if (!plate || core::dot(f.point, up) < core::dot(plate->point, up) - kOnBaseMm ||
        (std::fabs(core::dot(f.point, up) - core::dot(plate->point, up)) <= kOnBaseMm && f.area_mm2 > plate->area_mm2)) {
      plate = &f;
    }
  }
  std::vector<mesh::Mesh> hanging;
  if (plate != nullptr && core::dot(plate->point, root.build_direction) > lowest + kOnBaseMm) {
    auto cut = mesh::cut_by_plane(mesh, plate->point, root.build_direction);
    if (cut && !cut.value().above.triangles.empty()) {
      root.mesh = std::move(cut.value().above);
      root.base_point = plate->point;
      hanging = shells_of(cut.value().below);
    }
  }
  tree.regions.push_back(std::move(root));
  for (mesh::Mesh& h : hanging) {
    Region r;
    r.id = static_cast<std::uint32_t>(tree.regions.size());
    r.parent = 0;
    r.build_direction = tree.regions[0].build_direction * -1.0;
    r.base_normal = r.build_direction;
    r.base_point = tree.regions[0].base_point;
    r.mesh = std::move(h);
    r.rule = "below the plate";
    tree.regions.push_back(std::move(r));
  }

  for (std::size_t li = 0; li < axis.links.size(); ++li) {
    const AxisLink& link = axis.links[li];
    if (!link.is_break) continue;
    const Vec3 from = axis.nodes[link.from].position, to = axis.nodes[link.to].position;
    const Vec3 dir = core::normalized(to - from);
    // The link before the break (Ruan's father link): the previous link ending at `from`.
    Vec3 father_dir = dir;
    for (const AxisLink& l : axis.links) {
      if (l.to == link.from) father_dir = core::normalized(axis.nodes[l.to].position - axis.nodes[l.from].position);
    }
    // The region holding the link's end.
    std::size_t host = 0;
    double best = -INFINITY;
    for (std::size_t r = 0; r < tree.regions.size(); ++r) {
      const double w = winding(tree.regions[r].mesh, to);
      if (w > best) best = w, host = r;
    }
    std::optional<Split> chosen;
    auto consider = [&](Vec3 point, Vec3 normal, const std::string& rule) {
      auto s = try_split(tree.regions[host], point, normal, to, dir, options.self_supporting_deg, rule);
      if (s && (!chosen || s->unsupported < chosen->unsupported - 1e-9)) chosen = std::move(s);
    };
    // Candidate faces: real planar faces (several facets, some area), nearest to the link first.
    std::vector<const PlanarFace*> near;
    for (const PlanarFace& f : faces) {
      if (f.concave_edge && f.facets >= kMinSplitFaceFacets && f.area_mm2 >= kMinSplitFaceMm2) near.push_back(&f);
    }
    std::sort(near.begin(), near.end(), [&](const PlanarFace* a, const PlanarFace* b) {
      return std::fabs(core::dot(a->point - from, a->normal)) < std::fabs(core::dot(b->point - from, b->normal));
    });
    std::size_t tried = 0;
    for (const PlanarFace* fp : near) {
      const PlanarFace& f = *fp;
      if (tried >= kMaxSplitCandidates) break;
      for (const Vec3 d : {dir, father_dir}) {
        if (std::min(angle_deg(f.normal, d), angle_deg(f.normal * -1.0, d)) > options.face_normal_tolerance_deg) continue;
        const double c = core::dot(f.point, d), lo = std::min(core::dot(from, d), core::dot(to, d)), hi = std::max(core::dot(from, d), core::dot(to, d));
        if (c < lo - kLinkOverlapMm || c > hi + kLinkOverlapMm) continue;
        ++tried;
        consider(f.point, f.normal, "planar face");
      }
    }
    if (!chosen || chosen->unsupported > 0.0) consider(from, dir, "fallback plane");
    if (!chosen) continue;  // the plane missed the region: nothing to split at this link
    Region child;
    child.id = static_cast<std::uint32_t>(tree.regions.size());
    child.parent = tree.regions[host].id;
    child.build_direction = chosen->direction;
    child.base_point = chosen->point;
    child.base_normal = chosen->normal;
    child.mesh = std::move(chosen->child);
    child.rule = chosen->rule;
    tree.regions[host].mesh = std::move(chosen->parent);
    tree.regions.push_back(std::move(child));
  }
  for (Region& r : tree.regions) {
    r.volume_mm3 = mesh::signed_volume(r.mesh);
    r.unsupported_area_mm2 = unsupported(r.mesh, r.build_direction, options.self_supporting_deg, r.base_point, r.base_normal);
    r.support_free = r.unsupported_area_mm2 == 0.0;
  }
  return tree;
}

}  // namespace polyaxis::analysis
