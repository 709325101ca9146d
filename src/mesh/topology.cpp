#include "polyaxis/mesh/topology.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>

#include "polyaxis/core/check.h"
#include "polyaxis/core/parallel_buckets.h"

namespace polyaxis::mesh {
namespace {

// Vertices per task when runs are matched.
constexpr std::size_t kVertexGrain = std::size_t{1} << 14;

// A half-edge's bucket entry: its larger endpoint, whether it runs from the larger to the smaller
// endpoint, and its id. Sorting the entries of a bucket groups the half-edges of one edge.
std::uint64_t entry(std::uint32_t other, bool downward, std::uint32_t h) {
  return static_cast<std::uint64_t>(other) << 33 | static_cast<std::uint64_t>(downward) << 32 | h;
}
std::uint32_t entry_other(std::uint64_t e) { return static_cast<std::uint32_t>(e >> 33); }
bool entry_downward(std::uint64_t e) { return ((e >> 32) & 1u) != 0; }
std::uint32_t entry_half_edge(std::uint64_t e) { return static_cast<std::uint32_t>(e); }

// Half-edges bucketed by their smaller endpoint (core::bucket_in_parts): within a bucket the
// entries come in half-edge order whatever the thread count. Returns the bucket starts (nv + 1)
// and fills BUCKET.
std::vector<std::uint32_t> bucket_half_edges(const Mesh& mesh, std::vector<std::uint64_t>& bucket) {
  return core::bucket_in_parts(mesh.triangles.size(), mesh.vertices.size(), bucket, [&](std::size_t f, auto&& put) {
    const Triangle& t = mesh.triangles[f];
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      put(std::min(a, b), entry(std::max(a, b), a > b, static_cast<std::uint32_t>(3 * f + k)));
    }
  });
}

struct EdgeCounts {
  std::uint64_t edges = 0, boundary = 0, nonmanifold = 0, misoriented = 0;
  EdgeCounts operator+(const EdgeCounts& o) const {
    return {edges + o.edges, boundary + o.boundary, nonmanifold + o.nonmanifold, misoriented + o.misoriented};
  }
};

// Matches the runs of one vertex's bucket (entries of one edge), setting opposites.
EdgeCounts match_runs(std::uint64_t* first, std::uint64_t* last, std::vector<std::uint32_t>& opposite) {
  if (first == last) return {};  // an unused vertex (and, with no faces at all, FIRST is null)
  // Buckets hold a vertex's few edges: an insertion sort.
  for (std::uint64_t* i = first + 1; i < last; ++i) {
    const std::uint64_t e = *i;
    std::uint64_t* j = i;
    for (; j > first && *(j - 1) > e; --j) *j = *(j - 1);
    *j = e;
  }
  EdgeCounts c;
  for (std::uint64_t* it = first; it != last;) {
    std::uint64_t* run_end = it + 1;
    while (run_end != last && entry_other(*run_end) == entry_other(*it)) ++run_end;
    ++c.edges;
    const auto count = run_end - it;
    if (count == 1) {
      ++c.boundary;
    } else if (count == 2) {
      const std::uint32_t h0 = entry_half_edge(it[0]), h1 = entry_half_edge(it[1]);
      opposite[h0] = h1;
      opposite[h1] = h0;
      if (entry_downward(it[0]) == entry_downward(it[1])) ++c.misoriented;
    } else {
      ++c.nonmanifold;
    }
    it = run_end;
  }
  return c;
}

}  // namespace

EdgeTopology build_topology(const Mesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  const std::size_t nh = 3 * mesh.triangles.size();
  POLYAXIS_CHECK(nh < kNoHalfEdge, "too many half-edges for 32-bit indices");
  POLYAXIS_CHECK(nv < (std::size_t{1} << 31), "too many vertices for the half-edge buckets");
  EdgeTopology topo;
  topo.opposite.assign(nh, kNoHalfEdge);
  std::vector<std::uint64_t> bucket;
  const std::vector<std::uint32_t> start = bucket_half_edges(mesh, bucket);
  const EdgeCounts counts = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, nv, kVertexGrain), EdgeCounts{},
      [&](const tbb::blocked_range<std::size_t>& r, EdgeCounts c) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
          c = c + match_runs(bucket.data() + start[v], bucket.data() + start[v + 1], topo.opposite);
        }
        return c;
      },
      [](const EdgeCounts& a, const EdgeCounts& b) { return a + b; });
  topo.edges = counts.edges;
  topo.boundary_edges = counts.boundary;
  topo.nonmanifold_edges = counts.nonmanifold;
  topo.misoriented_edges = counts.misoriented;
  return topo;
}

}  // namespace polyaxis::mesh
