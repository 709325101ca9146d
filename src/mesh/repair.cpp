#include "polyaxis/mesh/repair.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <bit>
#include <cmath>
#include <numeric>

#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/self_intersections.h"
#include "polyaxis/mesh/topology.h"
#include "repair_steps.h"

namespace polyaxis::mesh {
namespace {

// Largest merge distance as a share of the bounding-box diagonal (see repair()).
constexpr double kMaxMergeShareOfDiagonal = 1e-5;

}  // namespace

namespace detail {
namespace {

struct Cell {
  std::int64_t x, y, z;
  bool operator==(const Cell&) const = default;
};

std::uint64_t hash_cell(Cell c) {
  std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ULL;
  h ^= static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
  h ^= h >> 29;
  return h;
}

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

std::uint64_t merge_vertices(Mesh& mesh, double tol_mm, std::span<const std::uint32_t> candidates) {
  const std::size_t n = candidates.size();
  if (tol_mm <= 0.0 || n < 2) return 0;
  const double cell = 16.0 * tol_mm;  // a point is within tol of a cell face with probability 1/8
  constexpr std::uint32_t kEmpty = 0xffffffffu;
  auto point = [&](std::uint32_t i) { return mesh.vertices[candidates[i]]; };
  std::vector<Cell> cells(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3 p = point(i);
    cells[i] = {static_cast<std::int64_t>(std::floor(p.x / cell)), static_cast<std::int64_t>(std::floor(p.y / cell)),
                static_cast<std::int64_t>(std::floor(p.z / cell))};
  }
  // Cell table: open addressing, each slot the head of a chain of the points in that cell.
  std::size_t capacity = 1024;
  while (capacity < 2 * n) capacity *= 2;
  const std::uint64_t mask = capacity - 1;
  std::vector<std::uint32_t> head(capacity, kEmpty);
  std::vector<std::uint32_t> next(n, kEmpty);
  auto slot_of = [&](Cell c) {
    std::uint64_t s = hash_cell(c) & mask;
    while (head[s] != kEmpty && !(cells[head[s]] == c)) s = (s + 1) & mask;
    return s;
  };
  for (std::uint32_t i = static_cast<std::uint32_t>(n); i-- > 0;) {  // chains end up in index order
    const std::uint64_t s = slot_of(cells[i]);
    next[i] = head[s];
    head[s] = i;
  }
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  const double tol2 = tol_mm * tol_mm;
  std::uint64_t unions = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3 p = point(i);
    const Cell c = cells[i];
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double base = static_cast<double>(a == 0 ? c.x : (a == 1 ? c.y : c.z)) * cell;
      lo[a] = (p[a] - base <= tol_mm) ? -1 : 0;
      hi[a] = (base + cell - p[a] <= tol_mm) ? 1 : 0;
    }
    for (int dx = lo[0]; dx <= hi[0]; ++dx) {
      for (int dy = lo[1]; dy <= hi[1]; ++dy) {
        for (int dz = lo[2]; dz <= hi[2]; ++dz) {
          const Cell q{c.x + dx, c.y + dy, c.z + dz};
          const std::uint64_t s = slot_of(q);
          for (std::uint32_t j = head[s]; j != kEmpty && j < i; j = next[j]) {
            const Vec3 d = point(j) - p;
            if (dot(d, d) > tol2) continue;
            const std::uint32_t ri = find_root(parent, i), rj = find_root(parent, j);
            if (ri != rj) {
              parent[std::max(ri, rj)] = std::min(ri, rj);
              ++unions;
            }
          }
        }
      }
    }
  }
  if (unions == 0) return 0;
  // Each merged vertex takes the id (and position) of the lowest candidate in its cluster; the
  // vertices left unused are removed by the caller.
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  std::iota(remap.begin(), remap.end(), 0u);
  for (std::uint32_t i = 0; i < n; ++i) remap[candidates[i]] = candidates[find_root(parent, i)];
  for (Triangle& t : mesh.triangles) {
    for (auto& v : t) v = remap[v];
  }
  return unions;
}

std::vector<std::uint32_t> open_vertices(const Mesh& mesh, const EdgeTopology& topo) {
  std::vector<char> open(mesh.vertices.size(), 0);
  for (std::uint32_t h = 0; h < topo.opposite.size(); ++h) {
    if (topo.opposite[h] == kNoHalfEdge) open[half_edge_from(mesh, h)] = open[half_edge_to(mesh, h)] = 1;
  }
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < open.size(); ++v) {
    if (open[v]) out.push_back(v);
  }
  return out;
}

namespace {

constexpr double kMinTwiceArea = 2.0 * core::kDegenerateAreaMm2;
// Passes of cap flips at most (each flips caps apart from one another, then looks again: a cap
// whose neighbour was a cap too, a fan of collinear points, flips once that neighbour has).
constexpr int kMaxCapPasses = 64;

bool degenerate(const Mesh& mesh, const Triangle& t) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const Vec3 n = cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
  return dot(n, n) < kMinTwiceArea * kMinTwiceArea;
}

// The half-edge of cap F along its longest edge: its third vertex lies strictly inside that edge
// (not at an end: that is a needle, a face with a vanishing edge) and within ON_EDGE_MM of it, or
// the face is degenerate.
std::optional<std::uint32_t> cap_edge(const Mesh& mesh, std::uint32_t f, double on_edge_mm) {
  const Triangle& t = mesh.triangles[f];
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return std::nullopt;
  std::uint32_t k = 0;
  double longest = -1.0;
  for (std::uint32_t e = 0; e < 3; ++e) {
    const Vec3 d = mesh.vertices[t[(e + 1) % 3]] - mesh.vertices[t[e]];
    if (dot(d, d) > longest) longest = dot(d, d), k = e;
  }
  const Vec3 a = mesh.vertices[t[k]], c = mesh.vertices[t[(k + 1) % 3]], m = mesh.vertices[t[(k + 2) % 3]];
  const double along = dot(m - a, c - a) / longest;
  constexpr double kInside = 1e-6;  // of the edge's length, from either end
  if (!(along > kInside && along < 1.0 - kInside)) return std::nullopt;
  const Vec3 n = cross(c - a, m - a);  // |n| = the edge's length times M's height over it
  if (!degenerate(mesh, t) && dot(n, n) > on_edge_mm * on_edge_mm * longest) return std::nullopt;
  return 3 * f + k;
}

// Whether T has a corner within ON_EDGE_MM of the line of its longest edge.
bool thin(const Mesh& mesh, const Triangle& t, double on_edge_mm) {
  double longest = 0.0;
  for (int e = 0; e < 3; ++e) {
    const Vec3 d = mesh.vertices[t[(e + 1) % 3]] - mesh.vertices[t[e]];
    longest = std::max(longest, dot(d, d));
  }
  const Vec3 n = cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
  return dot(n, n) <= on_edge_mm * on_edge_mm * longest;
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

}  // namespace

std::uint64_t flip_caps(Mesh& mesh, double on_edge_mm) {
  std::uint64_t flipped = 0;
  for (int pass = 0; pass < kMaxCapPasses; ++pass) {
    const EdgeTopology topo = build_topology(mesh);
    std::vector<std::uint32_t> caps;
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
      if (cap_edge(mesh, f, on_edge_mm)) caps.push_back(f);
    }
    if (caps.empty()) break;
    std::vector<std::uint64_t> edges;  // every edge as it stands at the start of the pass
    edges.reserve(topo.opposite.size());
    for (std::uint32_t e = 0; e < topo.opposite.size(); ++e) edges.push_back(edge_key(half_edge_from(mesh, e), half_edge_to(mesh, e)));
    std::sort(edges.begin(), edges.end());
    std::vector<char> touched(mesh.triangles.size(), 0);  // faces changed in this pass
    std::vector<std::uint64_t> made;                       // edges made in this pass
    std::uint64_t this_pass = 0;
    for (const std::uint32_t f : caps) {
      const auto h = cap_edge(mesh, f, on_edge_mm);
      if (!h || touched[f]) continue;
      // The cap is part of a closed surface: each of its edges has one other face, which agrees.
      bool closed = true;
      for (std::uint32_t e = 3 * f; e < 3 * f + 3 && closed; ++e) {
        const std::uint32_t x = topo.opposite[e];
        closed = x != kNoHalfEdge && half_edge_from(mesh, x) == half_edge_to(mesh, e);
      }
      if (!closed) continue;
      const std::uint32_t o = topo.opposite[*h];
      const std::uint32_t g = o / 3;
      if (touched[g]) continue;
      const std::uint32_t a = half_edge_from(mesh, *h), c = half_edge_to(mesh, *h);
      const std::uint32_t m = mesh.triangles[f][(*h % 3 + 2) % 3], d = mesh.triangles[g][(o % 3 + 2) % 3];
      const Triangle first{a, d, m}, second{d, c, m};
      if (m == d || degenerate(mesh, first) || degenerate(mesh, second)) continue;
      // Nor caps themselves: within a fan of points all near one line, flips would go round for ever.
      if (thin(mesh, first, on_edge_mm) || thin(mesh, second, on_edge_mm)) continue;
      // The new edge M-D must not be one already (it would have three faces).
      const std::uint64_t key = edge_key(m, d);
      if (std::binary_search(edges.begin(), edges.end(), key) || std::find(made.begin(), made.end(), key) != made.end()) continue;
      mesh.triangles[f] = first, mesh.triangles[g] = second;
      touched[f] = touched[g] = 1;
      made.push_back(key);
      ++this_pass;
    }
    flipped += this_pass;
    if (this_pass == 0) break;
  }
  return flipped;
}

std::uint64_t remove_degenerate_faces(Mesh& mesh) {
  const std::size_t before = mesh.triangles.size();
  std::size_t out = 0;
  for (std::size_t f = 0; f < before; ++f) {
    const Triangle t = mesh.triangles[f];
    if (degenerate(mesh, t)) continue;
    mesh.triangles[out++] = t;
  }
  mesh.triangles.resize(out);
  return before - out;
}

std::uint64_t remove_duplicate_faces(Mesh& mesh, const EdgeTopology& topo) {
  if (topo.closed() && topo.misoriented_edges == 0) return 0;  // no face can have a candidate edge
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t h = 3 * f + k, o = topo.opposite[h];
      if (o == kNoHalfEdge || half_edge_from(mesh, h) == half_edge_from(mesh, o)) {
        candidates.push_back(f);
        break;
      }
    }
  }
  if (candidates.size() < 2) return 0;
  auto sorted_key = [&](std::uint32_t f) {
    Triangle t = mesh.triangles[f];
    std::sort(t.begin(), t.end());
    return t;
  };
  std::sort(candidates.begin(), candidates.end(), [&](std::uint32_t a, std::uint32_t b) {
    const Triangle ka = sorted_key(a), kb = sorted_key(b);
    return ka != kb ? ka < kb : a < b;
  });
  // Orientation of a face relative to its sorted key: even permutation = +1.
  auto parity = [&](std::uint32_t f) {
    const Triangle& t = mesh.triangles[f];
    const std::uint32_t m = std::min({t[0], t[1], t[2]});
    const std::size_t r = t[0] == m ? 0 : (t[1] == m ? 1 : 2);
    return t[(r + 1) % 3] < t[(r + 2) % 3] ? 1 : -1;
  };
  std::vector<char> drop(mesh.triangles.size(), 0);
  std::uint64_t dropped = 0;
  for (std::size_t i = 0; i < candidates.size();) {
    std::size_t j = i + 1;
    while (j < candidates.size() && sorted_key(candidates[j]) == sorted_key(candidates[i])) ++j;
    if (j - i > 1) {
      int balance = 0;
      for (std::size_t k = i; k < j; ++k) balance += parity(candidates[k]);
      // Keep one face of the surplus orientation (the first such), drop the rest.
      bool kept = false;
      for (std::size_t k = i; k < j; ++k) {
        const std::uint32_t f = candidates[k];
        if (!kept && balance != 0 && parity(f) == (balance > 0 ? 1 : -1)) {
          kept = true;
          continue;
        }
        drop[f] = 1;
        ++dropped;
      }
    }
    i = j;
  }
  if (dropped == 0) return 0;
  std::size_t out = 0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (!drop[f]) mesh.triangles[out++] = mesh.triangles[f];
  }
  mesh.triangles.resize(out);
  return dropped;
}

std::uint64_t remove_unused_vertices(Mesh& mesh) {
  constexpr std::uint32_t kUnused = 0xffffffffu;
  std::vector<std::uint32_t> remap(mesh.vertices.size(), kUnused);
  for (const Triangle& t : mesh.triangles) {
    for (auto v : t) remap[v] = 0;
  }
  std::uint32_t next = 0;
  std::size_t out = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (remap[v] == kUnused) continue;
    remap[v] = next++;
    mesh.vertices[out++] = mesh.vertices[v];
  }
  const std::uint64_t removed = mesh.vertices.size() - out;
  mesh.vertices.resize(out);
  if (removed > 0) {
    for (Triangle& t : mesh.triangles) {
      for (auto& v : t) v = remap[v];
    }
  }
  return removed;
}

}  // namespace detail

std::vector<std::string> RepairReport::lines() const {
  std::vector<std::string> out;
  auto add = [&](std::uint64_t n, const char* what) {
    if (n > 0) out.push_back(fmt::format("{} {}", n, what));
  };
  add(merged_vertices, "vertices merged within the merge tolerance");
  add(unused_vertices, "unused vertices removed");
  add(flipped_caps, "caps (faces with a vertex inside an edge) flipped into proper faces");
  add(degenerate_faces, "degenerate faces removed");
  add(duplicate_faces, "duplicate faces removed");
  add(nonmanifold_edges, "non-manifold edges found");
  add(split_vertices, "vertices split to make edges and vertices manifold");
  add(flipped_faces, "faces flipped to agree with their neighbours");
  add(inverted_shells, "inside-out shells turned outwards");
  add(holes_filled, "holes filled");
  add(hole_faces_added, "faces added to fill holes");
  add(open_holes, "holes left open (--allow-open)");
  add(interior_shells_removed, "interior shells removed (union of nested same-orientation shells)");
  add(self_intersecting_faces, "self-intersecting faces (slicing takes the nonzero union)");
  return out;
}

core::Result<RepairedMesh> repair(io::RawMesh raw, const RepairOptions& options) {
  using core::ErrorCode;
  RepairedMesh out;
  Mesh& mesh = out.mesh;
  mesh.vertices = std::move(raw.points);
  mesh.triangles = std::move(raw.triangles);
  RepairReport& report = out.report;

  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (auto v : mesh.triangles[f]) {
      if (v >= mesh.vertices.size()) {
        return core::make_error(ErrorCode::kInvalidInput, fmt::format("facet {} refers to vertex {} of {}", f, v, mesh.vertices.size()));
      }
    }
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3 p = mesh.vertices[v];
    if (!core::is_finite(p)) return core::make_error(ErrorCode::kInvalidInput, fmt::format("vertex {} is not finite", v));
    if (std::fabs(p.x) > core::kMaxCoordinateMm || std::fabs(p.y) > core::kMaxCoordinateMm || std::fabs(p.z) > core::kMaxCoordinateMm) {
      return core::make_error(ErrorCode::kInfeasible,
                              fmt::format("coordinates out of range: vertex {} at ({:g}, {:g}, {:g}) mm is beyond ±{:g} mm", v, p.x, p.y,
                                          p.z, core::kMaxCoordinateMm));
    }
  }

  report.unused_vertices = detail::remove_unused_vertices(mesh);
  // The merge distance never exceeds a small share of the part's size, so that a part drawn in
  // metres or microns is not collapsed into a point before the unit warning can be given.
  const double diagonal = norm(bounding_box(mesh).size());
  const double merge_mm = std::min(options.merge_mm, kMaxMergeShareOfDiagonal * diagonal);
  report.flipped_caps = detail::flip_caps(mesh, merge_mm);
  report.degenerate_faces = detail::remove_degenerate_faces(mesh);
  if (mesh.triangles.empty()) return core::make_error(ErrorCode::kInvalidInput, "no geometry: every face is degenerate");
  EdgeTopology topo = build_topology(mesh);
  // Only vertices on open or non-manifold edges can close a crack by merging (T9); on a closed
  // mesh nothing needs searching, and two shells that merely come close stay apart.
  if (!topo.closed()) {
    const std::vector<std::uint32_t> open = detail::open_vertices(mesh, topo);
    report.merged_vertices = detail::merge_vertices(mesh, merge_mm, open);
    if (report.merged_vertices > 0) {
      report.degenerate_faces += detail::remove_degenerate_faces(mesh);
      report.unused_vertices += detail::remove_unused_vertices(mesh) - report.merged_vertices;
      if (mesh.triangles.empty()) return core::make_error(ErrorCode::kInvalidInput, "no geometry: every face is degenerate");
      topo = build_topology(mesh);
    }
  }

  report.duplicate_faces = detail::remove_duplicate_faces(mesh, topo);
  if (report.duplicate_faces > 0) topo = build_topology(mesh);
  report.nonmanifold_edges = topo.nonmanifold_edges;
  report.split_vertices = detail::split_nonmanifold_vertices(mesh, topo);
  if (report.split_vertices > 0) topo = build_topology(mesh);
  if (topo.nonmanifold_edges > 0) {
    return core::make_error(ErrorCode::kInfeasible,
                            fmt::format("{} non-manifold edges remain after splitting vertices", topo.nonmanifold_edges));
  }

  std::vector<std::uint32_t> component;
  auto flipped = detail::orient_faces(mesh, topo, component);
  if (!flipped) return flipped.error();
  report.flipped_faces = flipped.value();
  if (report.flipped_faces > 0) topo = build_topology(mesh);

  auto holes = detail::fill_holes(mesh, topo, component, options.max_hole_edges, options.allow_open);
  if (!holes) return holes.error();
  report.holes_filled = holes.value().filled;
  report.hole_faces_added = holes.value().faces_added;
  report.open_holes = holes.value().left_open;

  if (report.hole_faces_added > 0) {  // the fill must have closed the loops without new defects
    topo = build_topology(mesh);
    if (topo.nonmanifold_edges > 0) {
      return core::make_error(ErrorCode::kInfeasible,
                              fmt::format("{} non-manifold edges after filling holes: the holes touch each other", topo.nonmanifold_edges));
    }
  }
  // Every non-manifold edge was split (or refused) above; only holes kept open leave boundaries.
  out.watertight = topo.boundary_edges == 0;
  out.manifold = topo.nonmanifold_edges == 0;
  const std::uint64_t inverted_before = report.inverted_shells;
  const bool several_components = !component.empty() && *std::max_element(component.begin(), component.end()) > 0;
  out.shells = detail::build_shells(mesh, component, report.open_holes == 0, report);
  report.unused_vertices += detail::remove_unused_vertices(mesh);  // renumbers vertices, not faces
  // Several shells are regrouped and inverted shells flipped: only then are half-edges renumbered.
  if (several_components || report.inverted_shells != inverted_before) topo = build_topology(mesh);
  out.topology = std::move(topo);

  if (options.check_self_intersections) {
    out.self_intersecting = self_intersecting_faces(mesh, &out.topology);
    report.self_intersecting_faces = out.self_intersecting.size();
    if (options.strict && !out.self_intersecting.empty()) {
      return core::make_error(ErrorCode::kInfeasible,
                              fmt::format("{} self-intersecting faces (first: facet {}) and --strict", out.self_intersecting.size(),
                                          out.self_intersecting.front()));
    }
  }

  const core::Vec3 size = bounding_box(mesh).size();
  const double extent = std::max({size.x, size.y, size.z});
  if (extent < core::kTinyPartMm) {
    out.warnings.push_back(fmt::format("the part is only {:g} mm across: are the units metres? try --scale 1000", extent));
  } else if (extent < core::kSuspectMetresMm) {
    out.warnings.push_back(fmt::format("the part is only {:g} mm across: if it is in metres use --scale 1000, in inches --scale 25.4", extent));
  } else if (extent > core::kSuspectMicronsMm) {
    out.warnings.push_back(fmt::format("the part is {:g} mm across: if it is in micrometres use --scale 0.001", extent));
  }
  return out;
}

}  // namespace polyaxis::mesh
