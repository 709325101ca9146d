// One test per fixed bug, with its minimised input.
#include <gtest/gtest.h>

#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::mesh {
namespace {

// fuzz_repair seed4: a hole whose minimum-area triangulation used a diagonal that was already an
// edge of the mesh, leaving a non-manifold edge after repair.
TEST(Regress, HoleFillNeverRepeatsAnExistingEdge) {
  io::RawMesh raw;
  raw.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}, {0, 0, 2}, {2, 0, 2}, {0, 2, 2}, {2, 2, 2}};
  raw.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {7, 2, 7}, {3, 1, 1}, {7, 4, 4}, {6, 1, 4}};
  RepairOptions options;
  options.allow_open = true;
  auto r = repair(raw, options);
  if (!r.ok()) {
    EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
    return;
  }
  EXPECT_EQ(build_topology(r.value().mesh).nonmanifold_edges, 0u);
  EXPECT_TRUE(r.value().manifold);
}

}  // namespace
}  // namespace polyaxis::mesh
