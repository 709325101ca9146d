#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <map>

#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"

namespace polyaxis::mesh {
namespace {

Mesh to_mesh(const io::RawMesh& raw) { return Mesh{raw.points, raw.triangles}; }

TEST(Topology, ClosedCubeHasEighteenPairedEdges) {
  const Mesh m = to_mesh(test::cube());
  const EdgeTopology t = build_topology(m);
  EXPECT_EQ(t.edges, 18u);
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.misoriented_edges, 0u);
  for (std::uint32_t h = 0; h < t.opposite.size(); ++h) {
    const std::uint32_t o = t.opposite[h];
    ASSERT_NE(o, kNoHalfEdge);
    EXPECT_EQ(t.opposite[o], h);
    EXPECT_EQ(half_edge_from(m, h), half_edge_to(m, o));
  }
}

TEST(Topology, TorusIsClosed) {
  const EdgeTopology t = build_topology(to_mesh(test::torus(10, 3, 24, 12)));
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.edges, 3u * 24 * 12);  // V - E + F = 0 for a torus
}

// A mesh large enough to be bucketed in several parts, with each kind of defect, against a match
// by an ordered map: every pairing and every count agree whatever the part count.
TEST(Topology, LargeMeshInPartsMatchesAnOrderedMap) {
  io::RawMesh raw = test::torus(40, 15, 400, 200);  // 160 000 faces
  std::swap(raw.triangles[1000][1], raw.triangles[1000][2]);   // three misoriented edges
  raw.triangles.erase(raw.triangles.begin() + 50000);            // a hole: three boundary edges
  raw.triangles.push_back({raw.triangles[90000][0], raw.triangles[90000][1], 7});  // a fin: one edge of three faces
  const Mesh m = to_mesh(raw);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> by_edge;
  for (std::uint32_t h = 0; h < 3 * m.triangles.size(); ++h) {
    const std::uint32_t a = half_edge_from(m, h), b = half_edge_to(m, h);
    by_edge[{std::min(a, b), std::max(a, b)}].push_back(h);
  }
  std::vector<std::uint32_t> opposite(3 * m.triangles.size(), kNoHalfEdge);
  std::uint64_t boundary = 0, nonmanifold = 0, misoriented = 0;
  for (const auto& [edge, hs] : by_edge) {
    if (hs.size() == 1) ++boundary;
    if (hs.size() > 2) ++nonmanifold;
    if (hs.size() != 2) continue;
    opposite[hs[0]] = hs[1];
    opposite[hs[1]] = hs[0];
    if (half_edge_from(m, hs[0]) == half_edge_from(m, hs[1])) ++misoriented;
  }
  for (int threads : {1, 4}) {
    tbb::task_arena arena(threads);
    const EdgeTopology t = arena.execute([&] { return build_topology(m); });
    EXPECT_EQ(t.edges, by_edge.size()) << threads;
    EXPECT_EQ(t.boundary_edges, boundary) << threads;
    EXPECT_EQ(t.nonmanifold_edges, nonmanifold) << threads;
    EXPECT_EQ(t.misoriented_edges, misoriented) << threads;
    EXPECT_EQ(t.opposite, opposite) << threads;
  }
  EXPECT_EQ(misoriented, 3u);
  EXPECT_EQ(nonmanifold, 1u);
}

// Found by fuzz_repair: vertices and no faces left an empty bucket array, and the insertion sort
// stepped past its null start (undefined behaviour under the sanitizers).
TEST(Topology, VerticesWithoutFaces) {
  const Mesh m{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}};
  const EdgeTopology t = build_topology(m);
  EXPECT_EQ(t.edges, 0u);
  EXPECT_TRUE(t.opposite.empty());
}

TEST(Topology, CountsBoundaryAndNonManifoldEdges) {
  io::RawMesh m = test::cube();
  m.triangles.pop_back();
  EXPECT_EQ(build_topology(to_mesh(m)).boundary_edges, 3u);
  io::RawMesh fin = test::cube();
  fin.points.push_back({5, 5, 20});
  fin.triangles.push_back({4, 5, 8});  // a fin on the top edge 4-5
  const EdgeTopology t = build_topology(to_mesh(fin));
  EXPECT_EQ(t.nonmanifold_edges, 1u);
  EXPECT_EQ(t.boundary_edges, 2u);
}

}  // namespace
}  // namespace polyaxis::mesh
