// Self-intersection test, after CGAL Polygon_mesh_processing::self_intersections: candidate
// pairs of faces whose bounding boxes overlap, found in a uniform grid of cells about twice a
// face's size (each pair taken once, in the cell holding the low corner of the two boxes'
// overlap) and checked cell by cell in parallel; CGAL's box_intersection_d where the faces are
// too uneven for a grid. Faces sharing a vertex whose fan is proven to project one to one onto a
// plane (embedded_fans: nearly every vertex of a clean mesh) meet only along their shared edge or
// vertex and are passed over (each cell entry carries its face's vertices, flagged, for this).
// The other pairs go to exact predicates (Epick), after a filter for faces sharing a vertex (one
// face's far edge surely on one side of the other's plane, in doubles under Shewchuk's error
// bound, then exactly: they meet at the vertex only):
// - no shared vertex: apart when one face surely lies on one side of the other's plane (in doubles
//   under the same bound), else do_intersect(triangle, triangle);
// - one shared vertex: the opposite edge of either face meets the other face;
// - a shared edge: the two opposite vertices are coplanar with the edge and on the same side.
// This is the only translation unit that includes CGAL.
#include "polyaxis/mesh/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>

#include "polyaxis/core/progress.h"

namespace polyaxis::mesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle3 = Kernel::Triangle_3;
using Segment3 = Kernel::Segment_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

Point to_point(Vec3 v) { return {v.x, v.y, v.z}; }

constexpr std::size_t kMinFacesPerPart = std::size_t{1} << 16;  // faces per part of a parallel count

// The sign of the orientation of D against the plane of (A, B, C) in doubles, when a forward error
// bound proves it (Shewchuk's orient3d with his bound o3derrboundA); 0 when it does not, and the
// caller asks CGAL's exact predicate. Neighbouring faces, the bulk of the candidate pairs, are
// mostly told apart here without building CGAL objects.
int sure_orientation(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) + (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  constexpr double kEpsilon = 0x1p-53;
  constexpr double kBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;
  const double bound = kBound * permanent;
  // Shewchuk's sign convention is the opposite of CGAL's orientation(p, q, r, s).
  if (det > bound) return -1;
  if (-det > bound) return 1;
  return 0;
}

// EMBEDDED (optional): vertices whose fan is proven to meet itself only along its edges (see
// embedded_fans); two faces sharing such a vertex do not intersect.
bool faces_intersect(const Mesh& mesh, std::size_t f, std::size_t g, const std::vector<std::uint8_t>* embedded = nullptr) {
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
        if (embedded != nullptr && (*embedded)[a[static_cast<std::size_t>(i)]]) return false;
      }
    }
  }
  const Vec3 va[3] = {mesh.corner(f, 0), mesh.corner(f, 1), mesh.corner(f, 2)};
  const Vec3 vb[3] = {mesh.corner(g, 0), mesh.corner(g, 1), mesh.corner(g, 2)};
  if (shared == 1) {
    // One face's far edge surely on one side of the other's plane: they meet at the vertex only.
    auto surely_one_side = [](const Vec3* t, Vec3 p, Vec3 q) {
      const int op = sure_orientation(t[0], t[1], t[2], p);
      return op != 0 && op == sure_orientation(t[0], t[1], t[2], q);
    };
    if (surely_one_side(vb, va[(ia + 1) % 3], va[(ia + 2) % 3]) || surely_one_side(va, vb[(ib + 1) % 3], vb[(ib + 2) % 3])) return false;
  }
  if (shared == 2) {
    // Faces on a shared edge meet beyond it only when folded flat onto each other: the far vertex
    // of one surely off the other's plane settles it.
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t v = b[static_cast<std::size_t>(j)];
      if (v != a[0] && v != a[1] && v != a[2] && sure_orientation(va[0], va[1], va[2], vb[j]) != 0) return false;
    }
  }
  if (shared == 0) {
    // Three vertices of one face surely on one side of the other's plane: the faces are apart.
    auto surely_apart = [](const Vec3* t, const Vec3* u) {
      const int o = sure_orientation(t[0], t[1], t[2], u[0]);
      return o != 0 && o == sure_orientation(t[0], t[1], t[2], u[1]) && o == sure_orientation(t[0], t[1], t[2], u[2]);
    };
    if (surely_apart(va, vb) || surely_apart(vb, va)) return false;
  }
  const Point pa[3] = {to_point(va[0]), to_point(va[1]), to_point(va[2])};
  const Point pb[3] = {to_point(vb[0]), to_point(vb[1]), to_point(vb[2])};
  const Triangle3 ta(pa[0], pa[1], pa[2]), tb(pb[0], pb[1], pb[2]);
  if (shared == 0) return CGAL::do_intersect(ta, tb);
  if (shared == 1) {
    // One face's far edge strictly on one side of the other's plane: that face touches the other's
    // plane at the shared vertex only.
    auto one_side = [](const Point* t, const Point& p, const Point& q) {
      const CGAL::Orientation op = CGAL::orientation(t[0], t[1], t[2], p), oq = CGAL::orientation(t[0], t[1], t[2], q);
      return op != CGAL::COPLANAR && op == oq;
    };
    if (one_side(pb, pa[(ia + 1) % 3], pa[(ia + 2) % 3]) || one_side(pa, pb[(ib + 1) % 3], pb[(ib + 2) % 3])) return false;
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


// The corner at VERTEX of the face of half-edge H, and the edge of that corner other than H.
std::uint32_t other_edge_at(const Mesh& mesh, std::uint32_t h, std::uint32_t vertex) {
  const std::uint32_t f = h / 3;
  const Triangle& t = mesh.triangles[f];
  const std::uint32_t c = t[0] == vertex ? 0u : (t[1] == vertex ? 1u : 2u);
  const std::uint32_t out = 3 * f + c, in = 3 * f + (c + 2) % 3;
  return h == out ? in : out;
}

// Margin of the fan proof below: a corner's projected sine, relative to its edges, at the least.
// Rounding in the doubles used is about 1e-15 relative, so a wedge kept as positive is positive and
// spans a pseudo-angle far above the rounding of the pseudo-angles.
constexpr double kWedgeMargin = 1e-9;
constexpr double kTurnSlack = 1e-6;  // in quarter turns of pseudo-angle

// A monotone stand-in for the angle of (X, Y) in [0, 4): a quarter turn per quadrant, no atan2.
double pseudo_angle(double x, double y) {
  if (y >= 0.0) return x >= 0.0 ? y / (x + y) : 1.0 - x / (y - x);
  return x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
}

// Whether the fan of VERTEX, walked from corner C0 across two-face edges, covers all CORNERS of the
// vertex and projects one to one onto the plane normal to the fan's mean normal: every corner's
// wedge turns the same way by a margin, and the wedges go round once (a closed fan) or less than
// once (an open one). Then two faces of the fan meet only at the vertex or along a shared edge:
// their projections meet only there. Each wedge's turn is the difference of its edges'
// pseudo-angles (mod 4); over a closed fan they add up to 4 per turn round the vertex.
bool fan_is_embedded(const Mesh& mesh, const EdgeTopology& topo, std::uint32_t vertex, std::uint32_t c0, std::uint32_t corners,
                     std::vector<std::uint32_t>& fan) {
  fan.assign(1, c0 / 3);
  bool closed = false;
  const std::uint32_t f0 = c0 / 3, k0 = c0 % 3;
  const std::uint32_t start_edges[2] = {3 * f0 + k0, 3 * f0 + (k0 + 2) % 3};
  for (const std::uint32_t first : start_edges) {
    for (std::uint32_t e = first; fan.size() <= corners;) {
      const std::uint32_t o = topo.opposite[e];
      if (o == kNoHalfEdge) break;
      if (o / 3 == f0) {
        closed = true;
        break;
      }
      fan.push_back(o / 3);
      e = other_edge_at(mesh, o, vertex);
    }
    if (closed) break;
  }
  if (fan.size() != corners) return false;
  const Vec3 p = mesh.vertices[vertex];
  Vec3 n{0, 0, 0};
  for (const std::uint32_t f : fan) n = n + face_area_vector(mesh, f);
  const double length = norm(n);
  if (!(length > 0.0)) return false;
  n = n / length;
  const Vec3 ref = std::fabs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalized(ref - n * dot(ref, n)), w = cross(n, u);
  double turn = 0.0;
  for (const std::uint32_t f : fan) {
    const Triangle& t = mesh.triangles[f];
    const std::size_t c = t[0] == vertex ? 0 : (t[1] == vertex ? 1 : 2);
    const Vec3 e1 = mesh.vertices[t[(c + 1) % 3]] - p, e2 = mesh.vertices[t[(c + 2) % 3]] - p;
    const double wedge = dot(n, cross(e1, e2));  // > kWedgeMargin·|e1|·|e2|, squared (no square roots)
    if (!(wedge > 0.0 && wedge * wedge > kWedgeMargin * kWedgeMargin * dot(e1, e1) * dot(e2, e2))) return false;
    double d = pseudo_angle(dot(e2, u), dot(e2, w)) - pseudo_angle(dot(e1, u), dot(e1, w));
    if (d < 0.0) d += 4.0;
    turn += d;
  }
  return closed ? std::fabs(turn - 4.0) < kTurnSlack : turn < 4.0 - kTurnSlack;
}

// Corners per vertex and each vertex's lowest corner, counted in parallel parts over the faces.
void count_corners(const Mesh& mesh, std::vector<std::uint32_t>& corners, std::vector<std::uint32_t>& first) {
  const std::size_t nv = mesh.vertices.size(), nf = mesh.triangles.size();
  const auto threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t parts = std::clamp<std::size_t>(nf / kMinFacesPerPart, 1, threads);
  std::vector<std::vector<std::uint32_t>> count(parts), lowest(parts);
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
    count[p].assign(nv, 0);
    lowest[p].assign(nv, kNoHalfEdge);
    for (std::size_t f = nf * p / parts; f < nf * (p + 1) / parts; ++f) {
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.triangles[f][k];
        if (count[p][v]++ == 0) lowest[p][v] = static_cast<std::uint32_t>(3 * f + k);
      }
    }
  });
  corners = std::move(count[0]);
  first = std::move(lowest[0]);
  for (std::size_t p = 1; p < parts; ++p) {
    for (std::size_t v = 0; v < nv; ++v) {
      if (corners[v] == 0) first[v] = lowest[p][v];
      corners[v] += count[p][v];
    }
  }
}

// Per vertex, whether its fan is proven embedded (fan_is_embedded). On a clean mesh nearly every
// vertex is, so the neighbouring pairs, most of the candidates, need no predicate; the others are
// decided exactly.
std::vector<std::uint8_t> embedded_fans(const Mesh& mesh, const EdgeTopology& topo) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<std::uint32_t> corners, first;
  count_corners(mesh, corners, first);
  std::vector<std::uint8_t> embedded(nv, 0);
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> scratch;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, std::size_t{1} << 12), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<std::uint32_t>& fan = scratch.local();
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      if (corners[v] > 0) embedded[v] = fan_is_embedded(mesh, topo, static_cast<std::uint32_t>(v), first[v], corners[v], fan) ? 1 : 0;
    }
  });
  return embedded;
}

}  // namespace

namespace {

// Candidate pairs from CGAL's box intersection (sequential): the fallback for uneven meshes.
void mark_by_boxes(const Mesh& mesh, const std::vector<Box>& boxes, std::vector<std::atomic<unsigned char>>& hit,
                   const std::vector<std::uint8_t>* embedded) {
  std::vector<Box> work = boxes;
  core::Progress progress("self-intersections", 0);  // candidate pairs checked (the total is not known)
  std::uint64_t pairs = 0;
  auto callback = [&](const Box& x, const Box& y) {
    if ((++pairs & 0xffff) == 0) progress.update(pairs);
    const std::size_t f = x.info(), g = y.info();
    if (hit[f].load(std::memory_order_relaxed) && hit[g].load(std::memory_order_relaxed)) return;
    if (faces_intersect(mesh, f, g, embedded)) hit[f].store(1, std::memory_order_relaxed), hit[g].store(1, std::memory_order_relaxed);
  };
  CGAL::box_self_intersection_d<CGAL::Sequential_tag>(work.begin(), work.end(), callback);
}

// A face's bounding box in floats rounded outwards (a box that holds the face's box): the grid's
// candidates are a superset of the exact ones, and the predicates decide them.
struct FaceBox {
  float lo[3], hi[3];
};

float below(double v) {
  const auto f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float above(double v) {
  const auto f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

std::vector<FaceBox> face_float_boxes(const Mesh& mesh) {
  std::vector<FaceBox> boxes(mesh.triangles.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f) {
      const Vec3 a = mesh.corner(f, 0), b = mesh.corner(f, 1), c = mesh.corner(f, 2);
      boxes[f] = {{below(std::min({a.x, b.x, c.x})), below(std::min({a.y, b.y, c.y})), below(std::min({a.z, b.z, c.z}))},
                  {above(std::max({a.x, b.x, c.x})), above(std::max({a.y, b.y, c.y})), above(std::max({a.z, b.z, c.z}))}};
    }
  });
  return boxes;
}

// A uniform grid over the faces' boxes: for each cell, the faces whose boxes reach into it.
struct FaceGrid {
  double origin[3] = {0, 0, 0}, cell = 1.0, per_cell = 1.0;  // per_cell = 1 / cell
  std::int64_t dims[3] = {1, 1, 1};
  std::vector<std::uint32_t> start, faces;  // faces of cell c: faces[start[c], start[c + 1])
  // Monotone in V, which is all the grid needs of it (each pair is found in one cell).
  std::int64_t index(double v, int k) const {
    return std::clamp(static_cast<std::int64_t>(std::floor((v - origin[k]) * per_cell)), std::int64_t{0}, dims[k] - 1);
  }
  std::int64_t index(const double* p, int k) const { return index(p[k], k); }
  std::int64_t cell_of(const double* p) const { return (index(p, 2) * dims[1] + index(p, 1)) * dims[0] + index(p, 0); }
};

// The grid, or none when the faces are too uneven for one (a face spanning many cells).
std::optional<FaceGrid> make_grid(const std::vector<FaceBox>& boxes) {
  if (boxes.empty()) return std::nullopt;
  FaceGrid g;
  double lo[3] = {boxes[0].lo[0], boxes[0].lo[1], boxes[0].lo[2]}, hi[3] = {lo[0], lo[1], lo[2]};
  double mean_size = 0.0;
  for (const FaceBox& b : boxes) {
    double size = 0.0;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min<double>(lo[k], b.lo[k]), hi[k] = std::max<double>(hi[k], b.hi[k]);
      size = std::max<double>(size, b.hi[k] - b.lo[k]);
    }
    mean_size += size;
  }
  mean_size /= static_cast<double>(boxes.size());
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(span > 0.0) || !std::isfinite(span)) return std::nullopt;
  g.cell = std::max(2.0 * mean_size, span * 1e-6);
  // At most about two cells a face.
  const double max_cells = 2.0 * static_cast<double>(boxes.size()) + 8.0;
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= std::floor((hi[k] - lo[k]) / g.cell) + 1.0;
    if (cells <= max_cells) break;
    g.cell *= 1.25;
  }
  g.per_cell = 1.0 / g.cell;
  for (int k = 0; k < 3; ++k) g.origin[k] = lo[k], g.dims[k] = static_cast<std::int64_t>(std::floor((hi[k] - lo[k]) / g.cell)) + 1;
  const auto cells = static_cast<std::size_t>(g.dims[0] * g.dims[1] * g.dims[2]);
  // Counting sort of (cell, face) entries in parts over the faces, counted and placed in parallel
  // (within a cell the faces stay in index order); too many entries means faces far larger than
  // the cell.
  auto for_cells = [&](const FaceBox& b, auto&& visit) {
    const double l[3] = {b.lo[0], b.lo[1], b.lo[2]}, h[3] = {b.hi[0], b.hi[1], b.hi[2]};
    for (std::int64_t z = g.index(l, 2); z <= g.index(h, 2); ++z) {
      for (std::int64_t y = g.index(l, 1); y <= g.index(h, 1); ++y) {
        for (std::int64_t x = g.index(l, 0); x <= g.index(h, 0); ++x) visit(static_cast<std::size_t>((z * g.dims[1] + y) * g.dims[0] + x));
      }
    }
  };
  const std::size_t nf = boxes.size();
  const auto threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t parts = std::clamp<std::size_t>(nf / kMinFacesPerPart, 1, threads);
  auto first_face = [&](std::size_t p) { return nf * p / parts; };
  const std::uint64_t max_entries = 16 * static_cast<std::uint64_t>(nf) + 64;
  std::vector<std::vector<std::uint32_t>> place(parts);  // per part: counts, then next slot per cell
  std::vector<std::uint64_t> part_entries(parts, 0);
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
    place[p].assign(cells, 0);
    for (std::size_t f = first_face(p); f < first_face(p + 1) && part_entries[p] <= max_entries; ++f) {
      for_cells(boxes[f], [&](std::size_t c) { ++place[p][c], ++part_entries[p]; });
    }
  });
  std::uint64_t entries = 0;
  for (const std::uint64_t e : part_entries) entries += e;
  if (entries > max_entries) return std::nullopt;
  g.start.assign(cells + 1, 0);
  std::uint32_t next = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    g.start[c] = next;
    for (auto& slot : place) {
      const std::uint32_t n = slot[c];
      slot[c] = next;
      next += n;
    }
  }
  g.start[cells] = next;
  g.faces.resize(entries);
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
    for (std::size_t f = first_face(p); f < first_face(p + 1); ++f) {
      for_cells(boxes[f], [&](std::size_t c) { g.faces[place[p][c]++] = static_cast<std::uint32_t>(f); });
    }
  });
  return g;
}

// A face's box in a cell, with where the box's low corner lies: the low corner of two boxes'
// overlap lies in the cell of the larger of their low cells on each axis (floor is monotonic), so
// in this cell exactly when, on every axis, one of the two boxes starts in this cell's slab (both
// start in it or before it). Bit k of LOW_HERE: the box starts in this cell's slab along axis k.
struct CellEntry {
  FaceBox box;
  std::uint32_t face;
  std::uint32_t corners[3];  // the face's vertices, kEmbeddedBit set on those with an embedded fan
  std::uint8_t low_here;
};
constexpr std::uint8_t kLowHereAll = 7;

// Marks a vertex id whose fan is embedded (embedded_fans), on meshes whose ids all stay below it.
constexpr std::uint32_t kEmbeddedBit = std::uint32_t{1} << 31;

// Whether two faces share a vertex whose fan is embedded: then they meet only along their shared
// edge or vertex (embedded_fans), decided from the entries without reading the mesh.
bool share_embedded_vertex(const CellEntry& a, const CellEntry& b) {
  for (const std::uint32_t v : a.corners) {
    if ((v & kEmbeddedBit) != 0 && (v == b.corners[0] || v == b.corners[1] || v == b.corners[2])) return true;
  }
  return false;
}

bool overlap(const FaceBox& a, const FaceBox& b) {
  for (int k = 0; k < 3; ++k) {
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  }
  return true;
}

std::vector<Box> face_boxes(const Mesh& mesh) {
  std::vector<Box> boxes(mesh.triangles.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes.size(), 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f) {
      const Vec3 a = mesh.corner(f, 0), b = mesh.corner(f, 1), c = mesh.corner(f, 2);
      double lo[3] = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
      double hi[3] = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
      boxes[f] = Box(lo, hi, f);
    }
  });
  return boxes;
}

std::vector<std::uint32_t> marked(const std::vector<std::atomic<unsigned char>>& hit) {
  std::vector<std::uint32_t> faces;
  for (std::size_t f = 0; f < hit.size(); ++f) {
    if (hit[f].load(std::memory_order_relaxed)) faces.push_back(static_cast<std::uint32_t>(f));
  }
  return faces;
}

}  // namespace

std::vector<std::uint32_t> detail::self_intersecting_faces_by_boxes(const Mesh& mesh) {
  std::vector<std::atomic<unsigned char>> hit(mesh.triangles.size());
  mark_by_boxes(mesh, face_boxes(mesh), hit, nullptr);  // every pair decided by the predicates alone
  return marked(hit);
}

std::vector<std::uint32_t> self_intersecting_faces(const Mesh& mesh, const EdgeTopology* topology) {
  const std::vector<FaceBox> boxes = face_float_boxes(mesh);
  std::vector<std::atomic<unsigned char>> hit(mesh.triangles.size());
  const std::vector<std::uint8_t> embedded = embedded_fans(mesh, topology != nullptr ? *topology : build_topology(mesh));
  const std::optional<FaceGrid> grid = make_grid(boxes);
  if (!grid) {
    mark_by_boxes(mesh, face_boxes(mesh), hit, &embedded);
  } else {
    const FaceGrid& g = *grid;
    const std::size_t cells = g.start.size() - 1;
    core::Progress progress("self-intersections", cells);
    std::atomic<std::size_t> done{0};
    std::mutex progress_mutex;
    const bool flag_ids = mesh.vertices.size() < kEmbeddedBit;
    auto flagged = [&](std::uint32_t v) { return flag_ids && embedded[v] ? v | kEmbeddedBit : v; };
    tbb::enumerable_thread_specific<std::vector<CellEntry>> scratch;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<CellEntry>& entries = scratch.local();
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        if (g.start[c + 1] - g.start[c] < 2) continue;
        const auto cell = static_cast<std::int64_t>(c);
        const std::int64_t cell_xyz[3] = {cell % g.dims[0], cell / g.dims[0] % g.dims[1], cell / (g.dims[0] * g.dims[1])};
        entries.clear();
        for (std::uint32_t i = g.start[c]; i < g.start[c + 1]; ++i) {
          const std::uint32_t f = g.faces[i];
          const Triangle& t = mesh.triangles[f];
          const FaceBox& b = boxes[f];
          std::uint8_t low_here = 0;
          for (int k = 0; k < 3; ++k) low_here |= static_cast<std::uint8_t>(g.index(b.lo[k], k) == cell_xyz[k] ? 1 << k : 0);
          entries.push_back({b, f, {flagged(t[0]), flagged(t[1]), flagged(t[2])}, low_here});
        }
        // Sweep and prune along x: a box meets only the boxes that start before it ends.
        std::sort(entries.begin(), entries.end(), [](const CellEntry& x, const CellEntry& y) {
          return x.box.lo[0] != y.box.lo[0] ? x.box.lo[0] < y.box.lo[0] : x.face < y.face;
        });
        for (std::size_t i = 0; i < entries.size(); ++i) {
          const FaceBox& a = entries[i].box;
          const std::uint8_t la = entries[i].low_here;
          for (std::size_t j = i + 1; j < entries.size() && entries[j].box.lo[0] <= a.hi[0]; ++j) {
            const FaceBox& b = entries[j].box;
            // Each pair once: in the cell of the low corner of the two boxes' overlap.
            if ((la | entries[j].low_here) != kLowHereAll) continue;
            if (!overlap(a, b) || (flag_ids && share_embedded_vertex(entries[i], entries[j]))) continue;
            const std::size_t f = entries[i].face, h = entries[j].face;
            if (hit[f].load(std::memory_order_relaxed) && hit[h].load(std::memory_order_relaxed)) continue;
            if (faces_intersect(mesh, f, h, &embedded)) hit[f].store(1, std::memory_order_relaxed), hit[h].store(1, std::memory_order_relaxed);
          }
        }
      }
      const std::size_t now = done.fetch_add(range.size()) + range.size();
      if (std::unique_lock<std::mutex> lock(progress_mutex, std::try_to_lock); lock.owns_lock()) progress.update(now);
    });
  }
  return marked(hit);
}

}  // namespace polyaxis::mesh
