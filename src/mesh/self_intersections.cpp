// Self-intersection test, after CGAL Polygon_mesh_processing::self_intersections: candidate
// pairs from box_intersection_d over face bounding boxes, then exact predicates (Epick):
// - no shared vertex: do_intersect(triangle, triangle);
// - one shared vertex: the opposite edge of either face meets the other face;
// - a shared edge: the two opposite vertices are coplanar with the edge and on the same side.
// This is the only translation unit that includes CGAL.
#include "polyaxis/mesh/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <mutex>

#include "polyaxis/core/progress.h"

namespace polyaxis::mesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle3 = Kernel::Triangle_3;
using Segment3 = Kernel::Segment_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

Point to_point(Vec3 v) { return {v.x, v.y, v.z}; }

bool faces_intersect(const Mesh& mesh, std::size_t f, std::size_t g) {
  const Triangle& a = mesh.triangles[f];
  const Triangle& b = mesh.triangles[g];
  int shared = 0;
  int ia = -1, ib = -1;  // positions of a shared vertex in a and b
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (a[static_cast<std::size_t>(i)] == b[static_cast<std::size_t>(j)]) {
        ++shared;
        ia = i;
        ib = j;
      }
    }
  }
  const Point pa[3] = {to_point(mesh.corner(f, 0)), to_point(mesh.corner(f, 1)), to_point(mesh.corner(f, 2))};
  const Point pb[3] = {to_point(mesh.corner(g, 0)), to_point(mesh.corner(g, 1)), to_point(mesh.corner(g, 2))};
  const Triangle3 ta(pa[0], pa[1], pa[2]), tb(pb[0], pb[1], pb[2]);
  if (shared == 0) return CGAL::do_intersect(ta, tb);
  if (shared == 1) {
    const Segment3 opposite_a(pa[(ia + 1) % 3], pa[(ia + 2) % 3]);
    const Segment3 opposite_b(pb[(ib + 1) % 3], pb[(ib + 2) % 3]);
    return CGAL::do_intersect(opposite_a, tb) || CGAL::do_intersect(opposite_b, ta);
  }
  if (shared == 2) {
    // The vertex of each face not on the shared edge.
    int la = 0, lb = 0;
    for (int i = 0; i < 3; ++i) {
      if (a[static_cast<std::size_t>(i)] != b[0] && a[static_cast<std::size_t>(i)] != b[1] && a[static_cast<std::size_t>(i)] != b[2]) la = i;
      if (b[static_cast<std::size_t>(i)] != a[0] && b[static_cast<std::size_t>(i)] != a[1] && b[static_cast<std::size_t>(i)] != a[2]) lb = i;
    }
    const Point& p = pa[(la + 1) % 3];
    const Point& q = pa[(la + 2) % 3];
    if (!CGAL::coplanar(p, q, pa[la], pb[lb])) return false;
    return CGAL::coplanar_orientation(p, q, pa[la], pb[lb]) == CGAL::POSITIVE;
  }
  return true;  // three shared vertices: a duplicate face
}

}  // namespace

std::vector<std::uint32_t> self_intersecting_faces(const Mesh& mesh) {
  std::vector<Box> boxes;
  boxes.reserve(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec3 a = mesh.corner(f, 0), b = mesh.corner(f, 1), c = mesh.corner(f, 2);
    double lo[3] = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
    double hi[3] = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
    boxes.emplace_back(lo, hi, f);
  }
  std::vector<char> hit(mesh.triangles.size(), 0);
  core::Progress progress("self-intersections", 0);  // candidate pairs checked (the total is not known)
  std::uint64_t pairs = 0;
  auto callback = [&](const Box& x, const Box& y) {
    if ((++pairs & 0xffff) == 0) progress.update(pairs);
    const std::size_t f = x.info(), g = y.info();
    if (hit[f] && hit[g]) return;
    if (faces_intersect(mesh, f, g)) hit[f] = hit[g] = 1;
  };
  CGAL::box_self_intersection_d<CGAL::Sequential_tag>(boxes.begin(), boxes.end(), callback);
  std::vector<std::uint32_t> faces;
  for (std::size_t f = 0; f < hit.size(); ++f) {
    if (hit[f]) faces.push_back(static_cast<std::uint32_t>(f));
  }
  return faces;
}

}  // namespace polyaxis::mesh
