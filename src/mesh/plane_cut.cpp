// Plane cuts with caps through CGAL::Polygon_mesh_processing::clip(tm, plane, clip_volume(true)),
// which keeps the negative side of the plane and closes it, and unions (corefinement). One of the
// two CGAL translation units. Exact constructions (Epeck). The pieces of one cut that stay together
// are put back as one solid (cut_off) before rounding: a mesh of shells touching along a cap
// crashed the next cut, and rounded caps of one cut no longer lie on one plane.
#include "polyaxis/mesh/plane_cut.h"

#include "polyaxis/core/tolerances.h"
#include "polyaxis/mesh/properties.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include <map>

namespace polyaxis::mesh {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

// A cut whose far side falls into more pieces than the child and this many is refused (cut_off).
constexpr std::size_t kMaxRejoinedPieces = 3;

SurfaceMesh to_surface_mesh(const Mesh& mesh) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vs;
  vs.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) vs.push_back(sm.add_vertex(Point(v.x, v.y, v.z)));
  for (const Triangle& t : mesh.triangles) sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
  return sm;
}

// SM with its coordinates rounded to doubles.
Mesh to_mesh(const SurfaceMesh& sm) {
  Mesh out;
  std::map<SurfaceMesh::Vertex_index, std::uint32_t> index;
  for (auto v : sm.vertices()) {
    index[v] = static_cast<std::uint32_t>(out.vertices.size());
    const Point& p = sm.point(v);
    out.vertices.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  std::vector<std::uint32_t> corners;
  for (auto f : sm.faces()) {
    corners.clear();
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      corners.push_back(index[v]);
      if (corners.size() > sm.number_of_vertices()) break;  // a broken cycle: never loop forever
    }
    // Corefinement keeps a triangle mesh; any other face is fanned here (PMP::triangulate_faces
    // can loop on the degenerate faces a cut through a vertex leaves).
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  return out;
}


// SM clipped to the negative side of the plane (POINT, NORMAL), capped.
core::Status keep_negative(SurfaceMesh& sm, Vec3 point, Vec3 normal) {
  const Kernel::Plane_3 plane(Point(point.x, point.y, point.z), Kernel::Vector_3(normal.x, normal.y, normal.z));
  try {
    if (!PMP::clip(sm, plane, CGAL::parameters::clip_volume(true))) {
      return core::make_error(core::ErrorCode::kInfeasible, "the plane cut failed (is the part self-intersecting?)");
    }
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInfeasible, std::string("the plane cut failed: ") + e.what());
  }
  sm.collect_garbage();
  if (!CGAL::is_valid_polygon_mesh(sm)) {
    return core::make_error(core::ErrorCode::kInfeasible, "the plane cut left an invalid mesh (is the part self-intersecting?)");
  }
  return {};
}


core::Result<SurfaceMesh> united(std::vector<SurfaceMesh> pieces) {
  if (pieces.empty()) return SurfaceMesh{};
  SurfaceMesh sum = std::move(pieces[0]);
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    SurfaceMesh out;
    try {
      if (!PMP::corefine_and_compute_union(sum, pieces[i], out)) {
        return core::make_error(core::ErrorCode::kInfeasible,
                                "the union of the pieces failed (they would meet along an edge or a point only)");
      }
    } catch (const std::exception& e) {
      return core::make_error(core::ErrorCode::kInfeasible, std::string("the union of the pieces failed: ") + e.what());
    }
    sum = std::move(out);
  }
  return sum;
}

}  // namespace

core::Result<PlaneCut> cut_by_plane(const Mesh& mesh, Vec3 point, Vec3 normal) {
  SurfaceMesh below = to_surface_mesh(mesh), above = below;
  if (auto st = keep_negative(below, point, normal); !st) return st.error();
  if (auto st = keep_negative(above, point, normal * -1.0); !st) return st.error();
  return PlaneCut{to_mesh(below), to_mesh(above)};
}

core::Result<CutOff> cut_off(const Mesh& mesh, Vec3 point, Vec3 normal, const PiecePicker& pick) {
  SurfaceMesh far_side = to_surface_mesh(mesh), near_side = far_side;
  if (auto st = keep_negative(far_side, point, normal * -1.0); !st) return st.error();
  if (auto st = keep_negative(near_side, point, normal); !st) return st.error();
  std::vector<SurfaceMesh> pieces;
  PMP::split_connected_components(far_side, pieces);
  // Solid pieces are chosen from; a cavity's closed surface (inward, negative volume) touches
  // nothing and goes along with the piece whose box holds it.
  std::vector<std::size_t> solids, cavities;
  std::vector<Mesh> rounded;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    rounded.push_back(to_mesh(pieces[i]));
    (signed_volume(rounded.back()) > 0.0 ? solids : cavities).push_back(i);
  }
  if (solids.empty() || near_side.number_of_faces() == 0) {
    return core::make_error(core::ErrorCode::kInfeasible, "the plane does not cut the part in two");
  }
  std::vector<Mesh> candidates;  // lent to PICK, then given back
  for (std::size_t i : solids) candidates.push_back(std::move(rounded[i]));
  const std::optional<std::size_t> chosen = pick(candidates);
  for (std::size_t k = 0; k < solids.size(); ++k) rounded[solids[k]] = std::move(candidates[k]);
  if (!chosen) return core::make_error(core::ErrorCode::kInfeasible, "no piece of the cut was taken");
  if (*chosen >= solids.size()) return core::make_error(core::ErrorCode::kInternal, "cut_off: the picked piece does not exist");
  const std::size_t child = solids[*chosen];
  // The parent: the near side with the other pieces put back onto it, united while exact (their
  // caps lie on one plane; rounded, they would not). A union runs in exact rationals where the
  // caps meet: at most kMaxRejoinedPieces are put back.
  if (solids.size() - 1 > kMaxRejoinedPieces) {
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("the plane cuts {} pieces off besides the child (at most {} are put back)", solids.size() - 1,
                                        kMaxRejoinedPieces));
  }
  std::vector<SurfaceMesh> rest{std::move(near_side)};
  for (std::size_t i : solids) {
    if (i != child) rest.push_back(std::move(pieces[i]));
  }
  auto joined = united(std::move(rest));
  if (!joined) return joined.error();
  Mesh parent = to_mesh(joined.value());
  CutOff out{std::move(rounded[child]), std::move(parent)};
  for (std::size_t i : cavities) {
    Mesh& host = winding_number(out.child, rounded[i].vertices.front()) > core::kInsideWindingNumber ? out.child : out.parent;
    const auto base = static_cast<std::uint32_t>(host.vertices.size());
    host.vertices.insert(host.vertices.end(), rounded[i].vertices.begin(), rounded[i].vertices.end());
    for (const Triangle& t : rounded[i].triangles) host.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return out;
}

core::Result<Mesh> unite(const std::vector<Mesh>& pieces) {
  std::vector<SurfaceMesh> exact;
  for (const Mesh& p : pieces) exact.push_back(to_surface_mesh(p));
  auto out = united(std::move(exact));
  if (!out) return out.error();
  return to_mesh(out.value());
}

core::Result<Mesh> difference(const Mesh& a, const Mesh& b) {
  SurfaceMesh sa = to_surface_mesh(a), sb = to_surface_mesh(b), out;
  try {
    if (!PMP::corefine_and_compute_difference(sa, sb, out)) {
      return core::make_error(core::ErrorCode::kInfeasible, "the difference of the solids failed (they would meet along an edge or a point only)");
    }
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInfeasible, std::string("the difference of the solids failed: ") + e.what());
  }
  return to_mesh(out);
}

core::Result<Mesh> without_crossings(const Mesh& mesh) {
  SurfaceMesh sm = to_surface_mesh(mesh);
  try {
    if (!PMP::experimental::autorefine_and_remove_self_intersections(sm)) {
      return core::make_error(core::ErrorCode::kInfeasible, "the surface's crossing faces could not all be removed");
    }
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInfeasible, std::string("the surface's crossing faces could not be removed: ") + e.what());
  }
  return to_mesh(sm);
}

Mesh grown(const Mesh& mesh, double by_mm) {
  std::vector<core::Vec3> normal(mesh.vertices.size());
  for (const Triangle& t : mesh.triangles) {
    const core::Vec3 n = core::normalized(core::cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]));
    for (int k = 0; k < 3; ++k) {
      const core::Vec3 p = mesh.vertices[t[static_cast<std::size_t>(k)]];
      const core::Vec3 a = core::normalized(mesh.vertices[t[static_cast<std::size_t>((k + 1) % 3)]] - p);
      const core::Vec3 b = core::normalized(mesh.vertices[t[static_cast<std::size_t>((k + 2) % 3)]] - p);
      const double corner = std::acos(std::clamp(core::dot(a, b), -1.0, 1.0));
      if (std::isfinite(corner) && std::isfinite(n.x)) normal[t[static_cast<std::size_t>(k)]] = normal[t[static_cast<std::size_t>(k)]] + n * corner;
    }
  }
  Mesh out = mesh;
  for (std::size_t i = 0; i < out.vertices.size(); ++i) {
    const double len = core::norm(normal[i]);
    if (len > 0.0) out.vertices[i] = out.vertices[i] + normal[i] * (by_mm / len);
  }
  return out;
}

}  // namespace polyaxis::mesh
