#include <gtest/gtest.h>

#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"

namespace polyaxis::mesh {
namespace {

Mesh solid(const io::RawMesh& raw) {
  auto r = repair(raw);
  EXPECT_TRUE(r.ok());
  return r.value().mesh;
}

void expect_closed(const Mesh& m) {
  const EdgeTopology t = build_topology(m);
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.misoriented_edges, 0u);
}

TEST(PlaneCut, CubeInTwoHalvesClosedAndCapped) {
  const Mesh cube = solid(test::cube());
  auto cut = cut_by_plane(cube, {0, 0, 4}, {0, 0, 1});
  ASSERT_TRUE(cut.ok()) << cut.error().message;
  expect_closed(cut.value().below);
  expect_closed(cut.value().above);
  EXPECT_NEAR(signed_volume(cut.value().below), 400.0, 1e-9);
  EXPECT_NEAR(signed_volume(cut.value().above), 600.0, 1e-9);
}

TEST(PlaneCut, LBlockArmAtItsRoot) {
  // Column 20x20x60 with the arm 50x20x20 at z 40..60 (Ruan Fig. 7): the plane x = 20.
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/l_block.stl");
  ASSERT_TRUE(read.ok());
  const Mesh l = solid(read.value().mesh);
  auto cut = cut_by_plane(l, {20, 0, 0}, {1, 0, 0});
  ASSERT_TRUE(cut.ok()) << cut.error().message;
  expect_closed(cut.value().below);
  expect_closed(cut.value().above);
  EXPECT_NEAR(signed_volume(cut.value().below), 24000.0, 1e-6);
  EXPECT_NEAR(signed_volume(cut.value().above), 20000.0, 1e-6);
}

TEST(PlaneCut, TiltedPlaneKeepsTheVolume) {
  const Mesh t = solid(test::torus(20, 6, 48, 24));
  const double v = signed_volume(t);
  auto cut = cut_by_plane(t, {3, -2, 1}, {0.3, 0.5, 0.8});
  ASSERT_TRUE(cut.ok());
  expect_closed(cut.value().below);
  expect_closed(cut.value().above);
  EXPECT_NEAR(signed_volume(cut.value().below) + signed_volume(cut.value().above), v, 1e-6 * v);
  EXPECT_GT(signed_volume(cut.value().below), 0.0);
  EXPECT_GT(signed_volume(cut.value().above), 0.0);
}

TEST(PlaneCut, PlaneMissingThePart) {
  auto cut = cut_by_plane(solid(test::cube()), {0, 0, 50}, {0, 0, 1});
  ASSERT_TRUE(cut.ok());
  EXPECT_NEAR(signed_volume(cut.value().below), 1000.0, 1e-9);
  EXPECT_TRUE(cut.value().above.triangles.empty());
}

}  // namespace
}  // namespace polyaxis::mesh
