// Distance-field skeleton (Dwivedi & Kovacevic §2.1): the field's values, the graph's branches and
// skeleton vectors on shapes whose medial axis is known, determinism across thread counts.
#include "polyaxis/analysis/skeleton.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"
#include "support/meshes.h"

namespace polyaxis::analysis {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

mesh::Mesh part(const std::string& name) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name + ".stl");
  EXPECT_TRUE(read.ok()) << name;
  auto r = mesh::repair(std::move(read.value().mesh));
  EXPECT_TRUE(r.ok()) << name;
  return std::move(r).value().mesh;
}

// Synthetic solids go in as they are: overlapping boxes are one solid to the winding number.
mesh::Mesh as_mesh(const io::RawMesh& raw) {
  mesh::Mesh m;
  m.vertices = raw.points;
  m.triangles = raw.triangles;
  return m;
}

// Closed prism approximating a cylinder of radius R about Z, z in [z0, z1], N sides.
io::RawMesh cylinder(double r, double z0, double z1, std::uint32_t n) {
  io::RawMesh m;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double t = 2.0 * std::numbers::pi * i / n;
    m.points.push_back({r * std::cos(t), r * std::sin(t), z0});
    m.points.push_back({r * std::cos(t), r * std::sin(t), z1});
  }
  m.points.push_back({0, 0, z0});
  m.points.push_back({0, 0, z1});
  const std::uint32_t bottom = 2 * n, top = 2 * n + 1;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = 2 * i, b = 2 * ((i + 1) % n);
    m.triangles.push_back({a, b, b + 1});
    m.triangles.push_back({a, b + 1, a + 1});
    m.triangles.push_back({bottom, b, a});
    m.triangles.push_back({top, a + 1, b + 1});
  }
  return m;
}

// CYLINDER(r, 0, length, n) turned by TILT about Y and moved to BASE: a rod leaving BASE along
// (sin tilt, 0, cos tilt).
io::RawMesh rod(Vec3 base, double r, double length, double tilt_rad, std::uint32_t n) {
  io::RawMesh m = cylinder(r, 0.0, length, n);
  const double c = std::cos(tilt_rad), s = std::sin(tilt_rad);
  for (Vec3& p : m.points) p = base + Vec3{c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
  return m;
}

double angle_between(Vec3 a, Vec3 b) { return std::acos(std::clamp(dot(normalized(a), normalized(b)), -1.0, 1.0)); }

std::string describe(const SkeletonGraph& g) {
  std::string s;
  char buf[256];
  std::snprintf(buf, sizeof buf, "voxel %.3f mm, inside %llu, ridge %llu, skeleton %llu voxels, %u spurs pruned\n", g.voxel_mm,
                static_cast<unsigned long long>(g.inside_voxels), static_cast<unsigned long long>(g.ridge_voxels),
                static_cast<unsigned long long>(g.skeleton_voxels), g.pruned_spurs);
  s += buf;
  for (const SkeletonNode& n : g.nodes) {
    std::snprintf(buf, sizeof buf, "  node %u (%.2f %.2f %.2f) r %.2f deg %u kind %d\n", n.id, n.position.x, n.position.y,
                  n.position.z, n.radius_mm, n.degree, static_cast<int>(n.kind));
    s += buf;
  }
  for (const SkeletonEdge& e : g.edges) {
    std::snprintf(buf, sizeof buf, "  edge %u -> %u len %.2f dir (%.3f %.3f %.3f)\n", e.from, e.to, e.length_mm, e.direction.x,
                  e.direction.y, e.direction.z);
    s += buf;
  }
  return s;
}

// Is there an edge whose skeleton vector lies within TOL of DIR and whose length is at least MIN?
bool has_edge_along(const SkeletonGraph& g, Vec3 dir, double tol_rad, double min_mm) {
  for (const SkeletonEdge& e : g.edges) {
    if (e.length_mm >= min_mm && angle_between(e.direction, dir) <= tol_rad) return true;
  }
  return false;
}

std::size_t count_kind(const SkeletonGraph& g, SkeletonNodeKind kind) {
  std::size_t n = 0;
  for (const SkeletonNode& node : g.nodes) n += node.kind == kind ? 1u : 0u;
  return n;
}

TEST(DistanceField, CentreOfABoxIsItsHalfWidth) {
  const mesh::Mesh m = as_mesh(test::box({0, 0, 0}, {40, 30, 20}));
  auto f = signed_distance_field(m);
  ASSERT_TRUE(f.ok()) << f.error().message;
  const DistanceField& field = f.value();
  EXPECT_NEAR(field.at({20, 15, 10}), 10.0, field.voxel_mm);  // one voxel: the EDT's half-voxel surface
  EXPECT_LT(field.at({-1.5, 15, 10}), 0.0);                   // outside, in the margin
  EXPECT_NEAR(field.at({20, 15, 3}), 3.0, field.voxel_mm);
  EXPECT_GT(field.inside_cells, 0u);
}

TEST(DistanceField, CavityIsOutside) {
  // A box with an inward-facing box inside: the cavity's centre is outside (winding number 0).
  const mesh::Mesh m = as_mesh(test::join(test::box({0, 0, 0}, {40, 40, 40}), test::flipped(test::box({10, 10, 10}, {30, 30, 30}))));
  auto f = signed_distance_field(m, {.voxel_mm = 1.0});
  ASSERT_TRUE(f.ok());
  EXPECT_NEAR(f.value().at({20, 20, 20}), -10.0, 1.0);
  EXPECT_NEAR(f.value().at({5, 20, 20}), 5.0, 1.0);
}

TEST(DistanceField, RefusesEmptyAndTooThin) {
  EXPECT_EQ(signed_distance_field(mesh::Mesh{}).error().code, core::ErrorCode::kInvalidInput);
  // Two 0.01 mm plates 2.8 mm apart on a 1 mm grid: the voxel centres (z = 0.605, 1.605, 2.605)
  // fall between them.
  const mesh::Mesh plate =
      as_mesh(test::join(test::box({0, 0, 0.2}, {10, 10, 0.21}), test::box({0, 0, 3.0}, {10, 10, 3.01})));
  auto f = signed_distance_field(plate, {.voxel_mm = 1.0});
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().code, core::ErrorCode::kInfeasible);
}

TEST(DistanceField, GridStaysUnderTheCellCap) {
  const mesh::Mesh m = as_mesh(test::box({0, 0, 0}, {100, 100, 100}));
  auto f = signed_distance_field(m, {.voxel_mm = 0.1, .max_cells = 200'000});
  ASSERT_TRUE(f.ok());
  const DistanceField& field = f.value();
  EXPECT_LE(static_cast<std::uint64_t>(field.nx) * field.ny * field.nz, 200'000u);
  EXPECT_GT(field.voxel_mm, 0.1);
}

TEST(Skeleton, BarHasOneStraightEdgeAlongItsLength) {
  const mesh::Mesh m = as_mesh(test::box({0, 0, 0}, {80, 20, 20}));
  auto s = skeleton(m);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const SkeletonGraph& g = s.value();
  SCOPED_TRACE(describe(g));
  if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
  EXPECT_EQ(count_kind(g, SkeletonNodeKind::kBranch), 0u);
  EXPECT_TRUE(has_edge_along(g, {1, 0, 0}, 15 * kDeg, 40.0) || has_edge_along(g, {-1, 0, 0}, 15 * kDeg, 40.0));
}

TEST(Skeleton, CylinderHasNoBranchAfterPruning) {
  const mesh::Mesh m = as_mesh(cylinder(10.0, 0.0, 70.0, 64));
  auto s = skeleton(m);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const SkeletonGraph& g = s.value();
  SCOPED_TRACE(describe(g));
  if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
  EXPECT_EQ(count_kind(g, SkeletonNodeKind::kBranch), 0u);
  EXPECT_TRUE(has_edge_along(g, {0, 0, 1}, 15 * kDeg, 30.0));
  for (const SkeletonEdge& e : g.edges) EXPECT_GE(e.direction.z, 0.0);  // away from the plate
}

TEST(Skeleton, LBlockFollowsColumnThenArm) {
  const mesh::Mesh m = part("l_block");
  auto s = skeleton(m);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const SkeletonGraph& g = s.value();
  SCOPED_TRACE(describe(g));
  if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
  EXPECT_TRUE(has_edge_along(g, {0, 0, 1}, 15 * kDeg, 20.0));
  EXPECT_TRUE(has_edge_along(g, {1, 0, 0}, 15 * kDeg, 25.0));
  EXPECT_GE(count_kind(g, SkeletonNodeKind::kBranch) + count_kind(g, SkeletonNodeKind::kCorner), 1u);
}

TEST(Skeleton, ColumnWithArmBranches) {
  // Column 20×20×90 with an arm 20×20 at z 35–55 reaching to x = 70: a T on its side.
  const mesh::Mesh m = as_mesh(test::join(test::box({0, 0, 0}, {20, 20, 90}), test::box({10, 0, 35}, {70, 20, 55})));
  auto s = skeleton(m);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const SkeletonGraph& g = s.value();
  SCOPED_TRACE(describe(g));
  if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
  ASSERT_GE(count_kind(g, SkeletonNodeKind::kBranch), 1u);
  EXPECT_TRUE(has_edge_along(g, {0, 0, 1}, 15 * kDeg, 15.0));
  EXPECT_TRUE(has_edge_along(g, {1, 0, 0}, 15 * kDeg, 25.0));
  // The branch point lies on the column's axis at the arm's height.
  bool found = false;
  for (const SkeletonNode& n : g.nodes) {
    if (n.kind != SkeletonNodeKind::kBranch) continue;
    // The largest ball in the junction sits a little towards the arm (its radius exceeds the
    // column's half-width there), so allow 6 mm off the axis: still well inside the column.
    found = found || (std::hypot(n.position.x - 10.0, n.position.y - 10.0) < 6.0 && std::abs(n.position.z - 45.0) < 8.0);
  }
  EXPECT_TRUE(found);
}

TEST(Skeleton, CylWalls5RadiatesAlongTheWalls) {
  const mesh::Mesh m = part("cyl_walls5");
  SkeletonOptions o;
  o.field.voxel_mm = 0.6;  // three voxels across the 2 mm walls
  auto s = skeleton(m, o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const SkeletonGraph& g = s.value();
  SCOPED_TRACE(describe(g));
  if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
  for (int i = 0; i < 5; ++i) {
    const double t = (18.0 + 72.0 * i) * kDeg;
    const Vec3 radial{std::cos(t), std::sin(t), 0.0};
    bool found = false;
    for (const SkeletonEdge& e : g.edges) {
      const Vec3 start = g.nodes[e.from].position;
      if (std::hypot(start.x, start.y) < 6.0 && angle_between(e.direction, radial) <= 15 * kDeg) found = true;
    }
    EXPECT_TRUE(found) << "wall at " << 18 + 72 * i << "°";
  }
}

TEST(Skeleton, YForkKeepsItsColumnAtEveryVoxelSize) {
  // A column of radius 6.5 and height 30 forking into two rods at ±35°. At some voxel sizes the
  // column's ridge is two voxels across; a sub-iteration that takes one side of it must not then
  // peel the other side from its end up into the fork.
  const double column_mm = 30.0;
  for (const double r : {5.0, 6.5}) {
    const mesh::Mesh m = as_mesh(test::join(test::join(cylinder(r, 0.0, column_mm, 96), rod({0, 0, column_mm - r}, r, 40.0, 35 * kDeg, 96)),
                                            rod({0, 0, column_mm - r}, r, 40.0, -35 * kDeg, 96)));
    for (const double voxel : {0.9, 1.0, 1.1, 1.18, 1.25, 1.4}) {
      SkeletonOptions o;
      o.field.voxel_mm = voxel;
      auto s = skeleton(m, o);
      ASSERT_TRUE(s.ok()) << s.error().message;
      const SkeletonGraph& g = s.value();
      SCOPED_TRACE(fmt::format("r {} voxel {}\n{}", r, voxel, describe(g)));
      if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
      EXPECT_EQ(count_kind(g, SkeletonNodeKind::kBranch), 1u);
      EXPECT_TRUE(has_edge_along(g, {0, 0, 1}, 15 * kDeg, 0.6 * column_mm - r));
    }
  }
}

void expect_same(const SkeletonGraph& a, const SkeletonGraph& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  ASSERT_EQ(a.edges.size(), b.edges.size());
  EXPECT_EQ(a.skeleton_voxels, b.skeleton_voxels);
  EXPECT_EQ(a.ridge_voxels, b.ridge_voxels);
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].position, b.nodes[i].position);
    EXPECT_EQ(a.nodes[i].radius_mm, b.nodes[i].radius_mm);
  }
  for (std::size_t i = 0; i < a.edges.size(); ++i) {
    EXPECT_EQ(a.edges[i].from, b.edges[i].from);
    EXPECT_EQ(a.edges[i].to, b.edges[i].to);
    EXPECT_EQ(a.edges[i].polyline, b.edges[i].polyline);
  }
}

TEST(Skeleton, SameGraphAtOneAndTwoThreads) {
  for (const char* name : {"hinge", "two_branches"}) {
    const mesh::Mesh m = part(name);
    SkeletonOptions one, two;
    one.field.threads = 1;
    two.field.threads = 2;
    auto a = skeleton(m, one);
    auto b = skeleton(m, two);
    ASSERT_TRUE(a.ok() && b.ok()) << name;
    SCOPED_TRACE(name);
    expect_same(a.value(), b.value());
  }
}

// Timing only: printed, never asserted (STYLE.md: tests never assert on time).
TEST(Skeleton, TimePerReferencePart) {
  for (const char* name : {"cyl_walls5", "dome_sphere", "hinge", "impeller", "l_block", "pen_rack", "spiral", "two_branches"}) {
    const mesh::Mesh m = part(name);
    const auto t0 = std::chrono::steady_clock::now();
    auto s = skeleton(m);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(s.ok()) << name << ": " << s.error().message;
    const SkeletonGraph& g = s.value();
    if (std::getenv("POLYAXIS_SKELETON_DUMP") != nullptr) std::printf("%s", describe(g).c_str());
    std::printf("[ skeleton ] %-13s %8.1f ms  voxel %.3f mm  %zu nodes (%zu branch)  %zu edges  %llu skeleton voxels\n", name,
                ms, g.voxel_mm, g.nodes.size(), count_kind(g, SkeletonNodeKind::kBranch), g.edges.size(),
                static_cast<unsigned long long>(g.skeleton_voxels));
  }
}

}  // namespace
}  // namespace polyaxis::analysis
