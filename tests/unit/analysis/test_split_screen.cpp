// The screening of a split (split_screen.h): a cut that would leave a piece thinner on average than
// a region can be laid is not a split, before any exact cut is paid for.
#include <gtest/gtest.h>

#include "analysis/split_screen.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::analysis::detail {
namespace {

Screened screen(const mesh::RepairedMesh& part, double plane_z, double min_thickness_mm) {
  const HostFaces faces = host_faces(part.mesh, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, 30.0);
  HostRegion host{&part.mesh, &part.topology, {0, 0, 1}, {0, 0, 0}, {0, 0, 1}, false, {}, &faces, min_thickness_mm};
  std::vector<std::uint32_t> seeds;  // the facets of the top face
  for (std::uint32_t f = 0; f < part.mesh.triangles.size(); ++f) {
    if (part.mesh.corner(f, 0).z > 9.99 && part.mesh.corner(f, 1).z > 9.99 && part.mesh.corner(f, 2).z > 9.99) seeds.push_back(f);
  }
  const Vec3 starts[] = {{0, 0, 1}};
  return screen_split(host, {0, 0, plane_z}, {0, 0, 1}, seeds, starts, 30.0);
}

// A 20 x 10 x 10 box cut across z: the slab above the plane is the child.
TEST(ScreenSplit, ASliverThinnerThanTheLeastRegionIsNoSplitAndAThickSlabIs) {
  const auto part = polyaxis::test::repaired(polyaxis::test::box({0, 0, 0}, {20, 10, 10}));
  for (const double min_t : {0.3, 1.0}) {
    EXPECT_FALSE(screen(part, 10.0 - 0.2 * min_t, min_t).valid) << "a child 0.2 of the least thickness";
    EXPECT_FALSE(screen(part, 0.2 * min_t, min_t).valid) << "a parent 0.2 of the least thickness";
    EXPECT_TRUE(screen(part, 10.0 - 3.0 * min_t, min_t).valid) << "a child 3 times the least thickness";
    EXPECT_TRUE(screen(part, 3.0 * min_t, min_t).valid) << "a parent 3 times the least thickness";
  }
  EXPECT_TRUE(screen(part, 9.9, 0.0).valid) << "without a least thickness any slab is a split";
}

}  // namespace
}  // namespace polyaxis::analysis::detail
