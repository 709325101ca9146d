// Hole filling: boundary loops triangulated by the minimum-area dynamic programme of
// Barequet & Sharir (1995) as used by Liepa (2003, "Filling holes in meshes", §3.1, without the
// dihedral-angle term): W(i,k) = min over i<m<k of W(i,m) + W(m,k) + area(v_i, v_m, v_k).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "repair_steps.h"

namespace polyaxis::mesh::detail {
namespace {

double triangle_area(Vec3 a, Vec3 b, Vec3 c) { return norm(cross(b - a, c - a)) / 2.0; }

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

// Appends the triangles of the minimum-area triangulation of LOOP, reversed so that their edges
// run against the loop (the loop follows the existing faces' half-edges). A diagonal that is
// already an edge of the mesh is never used (it would make that edge non-manifold); when no
// triangulation avoids them, the loop is closed by a fan around a new centre vertex.
void triangulate_loop(Mesh& mesh, const std::vector<std::uint32_t>& loop, const std::set<std::uint64_t>& existing,
                      std::vector<Triangle>& out) {
  const std::size_t n = loop.size();
  if (n == 3) {
    out.push_back({loop[2], loop[1], loop[0]});
    return;
  }
  auto forbidden = [&](std::size_t i, std::size_t k) {  // (i, k) a diagonal, not a loop edge
    return !(k == i + 1 || (i == 0 && k == n - 1)) && existing.count(edge_key(loop[i], loop[k])) > 0;
  };
  std::vector<double> w(n * n, 0.0);
  std::vector<std::uint32_t> best(n * n, 0);
  auto at = [n](std::size_t i, std::size_t k) { return i * n + k; };
  for (std::size_t len = 2; len < n; ++len) {
    for (std::size_t i = 0; i + len < n; ++i) {
      const std::size_t k = i + len;
      double lowest = std::numeric_limits<double>::infinity();
      std::size_t arg = i + 1;
      for (std::size_t m = i + 1; m < k; ++m) {
        if (forbidden(i, m) || forbidden(m, k)) continue;
        const double cost = w[at(i, m)] + w[at(m, k)] +
                            triangle_area(mesh.vertices[loop[i]], mesh.vertices[loop[m]], mesh.vertices[loop[k]]);
        if (cost < lowest) lowest = cost, arg = m;
      }
      w[at(i, k)] = lowest;
      best[at(i, k)] = static_cast<std::uint32_t>(arg);
    }
  }
  if (!std::isfinite(w[at(0, n - 1)])) {
    Vec3 centre{};
    for (auto v : loop) centre = centre + mesh.vertices[v];
    const auto c = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(centre / static_cast<double>(n));
    for (std::size_t i = 0; i < n; ++i) out.push_back({loop[(i + 1) % n], loop[i], c});
    return;
  }
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, k] = stack.back();
    stack.pop_back();
    if (k < i + 2) continue;
    const std::size_t m = best[at(i, k)];
    out.push_back({loop[k], loop[m], loop[i]});
    stack.emplace_back(i, m);
    stack.emplace_back(m, k);
  }
}

}  // namespace

core::Result<HoleStats> fill_holes(Mesh& mesh, const EdgeTopology& topo, std::vector<std::uint32_t>& component,
                                   std::uint32_t max_edges, bool allow_open) {
  HoleStats stats;
  if (topo.boundary_edges == 0) return stats;
  const std::size_t nh = topo.opposite.size();
  // After splitting, a boundary vertex has exactly one outgoing boundary half-edge.
  std::vector<std::uint32_t> out_of(mesh.vertices.size(), kNoHalfEdge);
  for (std::uint32_t h = 0; h < nh; ++h) {
    if (topo.opposite[h] == kNoHalfEdge) out_of[half_edge_from(mesh, h)] = h;
  }
  // Edges between boundary vertices that the fill must not repeat.
  std::vector<char> on_boundary(mesh.vertices.size(), 0);
  for (std::uint32_t h = 0; h < nh; ++h) {
    if (topo.opposite[h] == kNoHalfEdge) on_boundary[half_edge_from(mesh, h)] = 1;
  }
  std::set<std::uint64_t> existing;
  for (std::uint32_t h = 0; h < nh; ++h) {
    const std::uint32_t a = half_edge_from(mesh, h), b = half_edge_to(mesh, h);
    if (on_boundary[a] && on_boundary[b]) existing.insert(edge_key(a, b));
  }
  std::vector<char> used(nh, 0);
  std::vector<std::uint32_t> loop;
  std::vector<Triangle> added;
  for (std::uint32_t start = 0; start < nh; ++start) {
    if (topo.opposite[start] != kNoHalfEdge || used[start]) continue;
    loop.clear();
    std::uint32_t h = start;
    while (!used[h]) {
      used[h] = 1;
      loop.push_back(half_edge_from(mesh, h));
      h = out_of[half_edge_to(mesh, h)];
      if (h == kNoHalfEdge) {
        return core::make_error(core::ErrorCode::kInfeasible,
                                fmt::format("open boundary through facet {} does not close into a loop", start / 3));
      }
    }
    if (h != start) {
      return core::make_error(core::ErrorCode::kInfeasible,
                              fmt::format("open boundary through facet {} does not close into a simple loop", start / 3));
    }
    if (loop.size() > max_edges) {
      if (allow_open) {
        ++stats.left_open;
        continue;
      }
      const Vec3 p = mesh.vertices[loop.front()];
      return core::make_error(core::ErrorCode::kInfeasible,
                              fmt::format("open mesh: a hole of {} edges near ({:g}, {:g}, {:g}) is larger than --max-hole-edges {} "
                                          "(use --allow-open to keep it)",
                                          loop.size(), p.x, p.y, p.z, max_edges));
    }
    const std::size_t before = added.size();
    triangulate_loop(mesh, loop, existing, added);
    for (std::size_t i = before; i < added.size(); ++i) {
      for (int e = 0; e < 3; ++e) existing.insert(edge_key(added[i][static_cast<std::size_t>(e)], added[i][static_cast<std::size_t>((e + 1) % 3)]));
    }
    for (std::size_t i = before; i < added.size(); ++i) component.push_back(component[start / 3]);
    ++stats.filled;
  }
  stats.faces_added = added.size();
  mesh.triangles.insert(mesh.triangles.end(), added.begin(), added.end());
  return stats;
}

}  // namespace polyaxis::mesh::detail
