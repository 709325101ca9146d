// Plane cuts with caps through CGAL::Polygon_mesh_processing::clip(tm, plane, clip_volume(true)),
// which keeps the negative side of the plane and closes it, and unions (corefinement). One of the
// two CGAL translation units. Exact constructions (Epeck). The pieces of one cut that stay together
// are put back as one solid (cut_off) before rounding: a mesh of shells touching along a cap
// crashed the next cut, and rounded caps of one cut no longer lie on one plane.
#include "polyaxis/mesh/plane_cut.h"

#include "polyaxis/core/tolerances.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/self_intersections.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include <map>
#include <optional>

namespace polyaxis::mesh {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

// Slack for comparing the boxes of exact points by their low x, mm: far more than their width.
constexpr double kBoxSlackMm = 1e-6;

// A face that crosses another is met by a plane passing within this of it, mm (far more than
// rounding; a cut that close would leave a sliver anyway).
constexpr double kCrossingClearMm = 1e-6;

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


// Whether the plane (POINT, NORMAL) meets a face of MESH that crosses another face: CGAL's clip
// is undefined there (two_branches, whose union leaves 16 such faces along the seam of its trunk
// and arm, crashed in it). Faces that cross far from the plane are cut around.
bool meets_crossing_faces(const Mesh& mesh, Vec3 point, Vec3 normal) {
  const Vec3 n = core::normalized(normal);
  for (const std::uint32_t f : self_intersecting_faces(mesh)) {
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      const double d = core::dot(mesh.corner(f, k) - point, n);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    if (lo <= kCrossingClearMm && hi >= -kCrossingClearMm) return true;
  }
  return false;
}

core::Status cuttable(const Mesh& mesh, Vec3 point, Vec3 normal) {
  if (!meets_crossing_faces(mesh, point, normal)) return {};
  return core::make_error(core::ErrorCode::kInfeasible, "the plane meets faces of the part that cross one another: no cut there");
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

// The caps a cut left on PLANE in SM: faces with every corner on it (exact), grouped by the edges
// they share, each with its area and centroid (rounded: the same cross-section capped on either
// side of the cut gives the same figures to rounding).
struct CapPatch {
  std::vector<SurfaceMesh::Face_index> faces;
  double area = 0.0;
  Vec3 centroid;
};

std::vector<CapPatch> cap_patches(const SurfaceMesh& sm, const Kernel::Plane_3& plane) {
  auto on_plane = [&](SurfaceMesh::Face_index f) {
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (!plane.has_on(sm.point(v))) return false;
    }
    return true;
  };
  std::vector<char> cap(sm.num_faces(), 0), seen(sm.num_faces(), 0);  // by face index
  for (auto f : sm.faces()) cap[f.idx()] = on_plane(f) ? 1 : 0;
  std::vector<CapPatch> out;
  for (auto f : sm.faces()) {
    if (!cap[f.idx()] || seen[f.idx()]) continue;
    CapPatch patch;
    Vec3 moment{0, 0, 0};
    std::vector<SurfaceMesh::Face_index> stack{f};
    seen[f.idx()] = 1;
    while (!stack.empty()) {
      const auto g = stack.back();
      stack.pop_back();
      patch.faces.push_back(g);
      std::vector<Vec3> c;
      for (auto v : CGAL::vertices_around_face(sm.halfedge(g), sm)) {
        const Point& q = sm.point(v);
        c.push_back({CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())});
      }
      const double a = 0.5 * core::norm(core::cross(c[1] - c[0], c[2] - c[0]));
      patch.area += a;
      moment = moment + (c[0] + c[1] + c[2]) * (a / 3.0);
      for (auto h : CGAL::halfedges_around_face(sm.halfedge(g), sm)) {
        const auto n = sm.face(sm.opposite(h));
        if (n != SurfaceMesh::null_face() && cap[n.idx()] && !seen[n.idx()]) seen[n.idx()] = 1, stack.push_back(n);
      }
    }
    patch.centroid = patch.area > 0.0 ? moment * (1.0 / patch.area) : moment;
    out.push_back(std::move(patch));
  }
  return out;
}

// The patch of PATCHES that caps the same cross-section as P, if any.
std::optional<std::size_t> same_section(const std::vector<CapPatch>& patches, const CapPatch& p) {
  const double tol = 1e-9 * std::max(1.0, p.area);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    if (std::abs(patches[i].area - p.area) <= tol && core::norm(patches[i].centroid - p.centroid) <= 1e-9 * std::max(1.0, core::norm(p.centroid))) return i;
  }
  return std::nullopt;
}

// Where a border vertex of SM lies strictly inside a border edge (exactly: the two clips cut the
// surface along one line, but each has points of its own on it where the clipping box's
// diagonal crossed), the edge is split there and its face cut in two, so that the two sides'
// borders meet vertex for vertex. Corners are found by their box along x: O(n log n) for n border
// edges, and a few per edge.
void split_at_t_junctions(SurfaceMesh& sm) {
  std::vector<SurfaceMesh::Halfedge_index> work;
  std::vector<std::pair<double, SurfaceMesh::Vertex_index>> corners;  // by the low x of their box
  for (auto h : sm.halfedges()) {
    if (sm.is_border(h)) work.push_back(h), corners.emplace_back(sm.point(sm.target(h)).bbox().xmin(), sm.target(h));
  }
  std::sort(corners.begin(), corners.end());
  while (!work.empty()) {
    const auto h = work.back();
    work.pop_back();
    const auto va = sm.source(h), vc = sm.target(h);
    const Point a = sm.point(va), c = sm.point(vc);  // copies: splitting adds a vertex, which may move the points
    const CGAL::Bbox_3 box = a.bbox() + c.bbox();
    // A corner's box is a few ulps wide at most: one whose low x lies kBoxSlackMm under the edge's
    // cannot reach it.
    const auto first = std::lower_bound(corners.begin(), corners.end(), box.xmin() - kBoxSlackMm,
                                        [](const auto& corner, double x) { return corner.first < x; });
    for (auto it = first; it != corners.end() && it->first <= box.xmax(); ++it) {
      const auto v = it->second;
      if (v == va || v == vc) continue;
      const Point b = sm.point(v);
      if (!CGAL::do_overlap(box, b.bbox()) || !CGAL::collinear(a, b, c) || !CGAL::collinear_are_strictly_ordered_along_line(a, b, c)) continue;
      // The triangle on the inner side, (c, a, x), becomes (c, b, a, x): cut through b and x.
      const auto hb = CGAL::Euler::split_edge(sm.opposite(h), sm);  // c -> b, followed by b -> a
      sm.point(sm.target(hb)) = b;
      CGAL::Euler::split_face(hb, sm.next(sm.next(hb)), sm);
      work.push_back(sm.opposite(hb));                // b -> c, on the border
      work.push_back(sm.opposite(sm.next(hb)));       // a -> b, on the border
      break;
    }
  }
}

// NEAR and PIECE, two sides of one cut by PLANE meeting on caps that cover the same
// cross-sections, as one solid: both caps dropped and the borders stitched (exact points), which
// corefinement would do at the cost of intersecting the coplanar caps in exact rationals. None
// when a cap of PIECE has no twin on NEAR or the result is not a closed, valid mesh.
std::optional<SurfaceMesh> glued(const SurfaceMesh& near, const SurfaceMesh& piece, const Kernel::Plane_3& plane) {
  const std::vector<CapPatch> near_caps = cap_patches(near, plane), piece_caps = cap_patches(piece, plane);
  if (piece_caps.empty()) return std::nullopt;
  std::vector<char> drop_near(near.num_faces(), 0), drop_piece(piece.num_faces(), 0);  // by face index
  std::vector<bool> used(near_caps.size(), false);
  for (const CapPatch& p : piece_caps) {
    const auto twin = same_section(near_caps, p);
    if (!twin || used[*twin]) return std::nullopt;
    used[*twin] = true;
    for (auto f : near_caps[*twin].faces) drop_near[f.idx()] = 1;
    for (auto f : p.faces) drop_piece[f.idx()] = 1;
  }
  SurfaceMesh out;
  auto append = [&](const SurfaceMesh& sm, const std::vector<char>& drop) {
    std::vector<SurfaceMesh::Vertex_index> to(sm.num_vertices());  // by vertex index
    for (auto v : sm.vertices()) to[v.idx()] = out.add_vertex(sm.point(v));
    for (auto f : sm.faces()) {
      if (drop[f.idx()]) continue;
      std::vector<SurfaceMesh::Vertex_index> c;
      for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) c.push_back(to[v.idx()]);
      if (out.add_face(c) == SurfaceMesh::null_face()) return false;
    }
    return true;
  };
  if (!append(near, drop_near) || !append(piece, drop_piece)) return std::nullopt;
  split_at_t_junctions(out);
  PMP::stitch_borders(out);
  out.collect_garbage();
  if (!CGAL::is_closed(out) || !CGAL::is_valid_polygon_mesh(out)) return std::nullopt;
  return out;
}

}  // namespace

core::Result<PlaneCut> cut_by_plane(const Mesh& mesh, Vec3 point, Vec3 normal) {
  if (auto st = cuttable(mesh, point, normal); !st) return st.error();
  SurfaceMesh below = to_surface_mesh(mesh), above = below;
  if (auto st = keep_negative(below, point, normal); !st) return st.error();
  if (auto st = keep_negative(above, point, normal * -1.0); !st) return st.error();
  return PlaneCut{to_mesh(below), to_mesh(above)};
}

core::Result<CutOff> cut_off(const Mesh& mesh, Vec3 point, Vec3 normal, const PiecePicker& pick) {
  if (auto st = cuttable(mesh, point, normal); !st) return st.error();
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
  // Each piece is glued onto the near side along the caps they share; a piece that cannot be is
  // united with it by corefinement.
  const Kernel::Plane_3 plane(Point(point.x, point.y, point.z), Kernel::Vector_3(normal.x, normal.y, normal.z));
  std::vector<SurfaceMesh> rest{std::move(near_side)};
  for (std::size_t i : solids) {
    if (i == child) continue;
    if (auto g = glued(rest.front(), pieces[i], plane)) {
      rest.front() = std::move(*g);
    } else {
      rest.push_back(std::move(pieces[i]));
    }
  }
  const std::size_t united_pieces = rest.size() - 1;
  auto joined = united(std::move(rest));
  if (!joined) return joined.error();
  Mesh parent = to_mesh(joined.value());
  CutOff out{std::move(rounded[child]), std::move(parent), united_pieces};
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

namespace {

// OP(a, b, out) of CGAL's corefinement booleans on A and B, named WHAT in its errors.
template <class Op>
core::Result<Mesh> corefined(const Mesh& a, const Mesh& b, const char* what, Op op) {
  SurfaceMesh sa = to_surface_mesh(a), sb = to_surface_mesh(b), out;
  try {
    if (!op(sa, sb, out)) {
      return core::make_error(core::ErrorCode::kInfeasible, fmt::format("the {} of the solids failed (they would meet along an edge or a point only)", what));
    }
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInfeasible, fmt::format("the {} of the solids failed: {}", what, e.what()));
  }
  return to_mesh(out);
}

}  // namespace

core::Result<Mesh> difference(const Mesh& a, const Mesh& b) {
  return corefined(a, b, "difference", [](SurfaceMesh& x, SurfaceMesh& y, SurfaceMesh& out) { return PMP::corefine_and_compute_difference(x, y, out); });
}

core::Result<Mesh> intersection(const Mesh& a, const Mesh& b) {
  return corefined(a, b, "intersection", [](SurfaceMesh& x, SurfaceMesh& y, SurfaceMesh& out) { return PMP::corefine_and_compute_intersection(x, y, out); });
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
