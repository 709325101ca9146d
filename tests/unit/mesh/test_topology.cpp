#include <gtest/gtest.h>

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
