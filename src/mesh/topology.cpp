#include "polyaxis/mesh/topology.h"

#include <algorithm>

#include "polyaxis/core/check.h"

namespace polyaxis::mesh {

EdgeTopology build_topology(const Mesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  const std::size_t nh = 3 * mesh.triangles.size();
  POLYAXIS_CHECK(nh < kNoHalfEdge, "too many half-edges for 32-bit indices");
  EdgeTopology topo;
  topo.opposite.assign(nh, kNoHalfEdge);

  // Counting sort of half-edges by their smaller endpoint.
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++start[std::min(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]) + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> bucket(nh);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t h = 0; h < nh; ++h) {
      const std::uint32_t a = half_edge_from(mesh, h), b = half_edge_to(mesh, h);
      bucket[fill[std::min(a, b)]++] = h;
    }
  }
  // Within a bucket, order by the larger endpoint (buckets hold a vertex's few edges), then by
  // half-edge id for determinism.
  auto other = [&](std::uint32_t h) { return std::max(half_edge_from(mesh, h), half_edge_to(mesh, h)); };
  for (std::size_t v = 0; v < nv; ++v) {
    const auto first = bucket.begin() + start[v], last = bucket.begin() + start[v + 1];
    if (last - first > 1) {
      std::sort(first, last, [&](std::uint32_t x, std::uint32_t y) {
        const std::uint32_t ox = other(x), oy = other(y);
        return ox != oy ? ox < oy : x < y;
      });
    }
    for (auto it = first; it != last;) {
      auto run_end = it + 1;
      while (run_end != last && other(*run_end) == other(*it)) ++run_end;
      const auto count = run_end - it;
      ++topo.edges;
      if (count == 1) {
        ++topo.boundary_edges;
      } else if (count == 2) {
        topo.opposite[it[0]] = it[1];
        topo.opposite[it[1]] = it[0];
        if (half_edge_from(mesh, it[0]) == half_edge_from(mesh, it[1])) ++topo.misoriented_edges;
      } else {
        ++topo.nonmanifold_edges;
      }
      it = run_end;
    }
  }
  return topo;
}

}  // namespace polyaxis::mesh
