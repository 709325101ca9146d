#include "mesh_union.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>

#include <map>
#include <stdexcept>

namespace polyaxis::test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

SurfaceMesh to_surface_mesh(const io::RawMesh& m) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vs;
  for (const core::Vec3& p : m.points) vs.push_back(sm.add_vertex(Point(p.x, p.y, p.z)));
  for (const auto& t : m.triangles) sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
  return sm;
}

}  // namespace

io::RawMesh mesh_union(const io::RawMesh& a, const io::RawMesh& b) {
  SurfaceMesh sa = to_surface_mesh(a), sb = to_surface_mesh(b), out;
  if (!CGAL::Polygon_mesh_processing::corefine_and_compute_union(sa, sb, out)) throw std::runtime_error("mesh_union: CGAL refused");
  io::RawMesh r;
  std::map<SurfaceMesh::Vertex_index, std::uint32_t> index;
  for (auto v : out.vertices()) {
    index[v] = static_cast<std::uint32_t>(r.points.size());
    const Point& p = out.point(v);
    r.points.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  for (auto f : out.faces()) {
    std::vector<std::uint32_t> c;
    for (auto v : CGAL::vertices_around_face(out.halfedge(f), out)) c.push_back(index[v]);
    for (std::size_t k = 1; k + 1 < c.size(); ++k) r.triangles.push_back({c[0], c[k], c[k + 1]});
  }
  return r;
}

}  // namespace polyaxis::test
