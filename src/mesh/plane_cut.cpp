// Plane cuts with caps through CGAL::Polygon_mesh_processing::clip(tm, plane, clip_volume(true)),
// which keeps the negative side of the plane and closes it. One of the two CGAL translation units.
#include "polyaxis/mesh/plane_cut.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Surface_mesh.h>

#include <map>

namespace polyaxis::mesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh to_surface_mesh(const Mesh& mesh) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vs;
  vs.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) vs.push_back(sm.add_vertex(Point(v.x, v.y, v.z)));
  for (const Triangle& t : mesh.triangles) sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
  return sm;
}

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
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  return out;
}

core::Result<Mesh> keep_negative(const Mesh& mesh, Vec3 point, Vec3 normal) {
  SurfaceMesh sm = to_surface_mesh(mesh);
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
  // Corefinement keeps a triangle mesh; to_mesh fans any other face (PMP::triangulate_faces can
  // loop on the degenerate faces a cut through a vertex leaves).
  return to_mesh(sm);
}

}  // namespace

core::Result<PlaneCut> cut_by_plane(const Mesh& mesh, Vec3 point, Vec3 normal) {
  auto below = keep_negative(mesh, point, normal);
  if (!below) return below.error();
  auto above = keep_negative(mesh, point, normal * -1.0);
  if (!above) return above.error();
  return PlaneCut{std::move(below.value()), std::move(above.value())};
}

}  // namespace polyaxis::mesh
