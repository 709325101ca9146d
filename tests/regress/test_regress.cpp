// One test per fixed bug, with its minimised input.
#include <gtest/gtest.h>

#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"

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

// A box poking out of the top of a column (a self-intersecting model of two overlapping solids)
// was dropped as an "interior shell": the centroid of its largest face lies inside the column.
TEST(Regress, OverlappingShellsAreNotNested) {
  io::RawMesh raw = test::join(test::box({0, 0, 0}, {20, 20, 60}), test::box({5, 5, 40}, {15, 15, 70}));
  auto r = repair(raw);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().shells.size(), 2u);
  EXPECT_EQ(r.value().report.interior_shells_removed, 0u);
}

}  // namespace
}  // namespace polyaxis::mesh
