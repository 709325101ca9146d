// Repair properties: closed, manifold, outward, consistent; and one test per topology row.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <utility>
#include <vector>

#include "polyaxis/core/tolerances.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/meshes.h"

namespace polyaxis::mesh {
namespace {

void expect_clean(const RepairedMesh& r) {
  const EdgeTopology t = build_topology(r.mesh);
  EXPECT_EQ(r.topology.opposite, t.opposite);  // the topology handed on matches the mesh
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.misoriented_edges, 0u);
  EXPECT_TRUE(r.watertight);
  EXPECT_TRUE(r.manifold);
  EXPECT_GT(signed_volume(r.mesh), 0.0);
}

TEST(Repair, CleanCubeIsUntouched) {
  auto r = repair(test::cube());
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_TRUE(r.value().report.lines().empty());
  EXPECT_DOUBLE_EQ(signed_volume(r.value().mesh), 1000.0);
  EXPECT_EQ(r.value().shells.size(), 1u);
}

TEST(Repair, IsIdempotent) {
  auto once = repair(test::soup(test::torus(20, 5, 40, 20)));
  ASSERT_TRUE(once.ok());
  io::RawMesh again{once.value().mesh.vertices, once.value().mesh.triangles};
  auto twice = repair(again);
  ASSERT_TRUE(twice.ok());
  EXPECT_TRUE(twice.value().report.lines().empty());
  EXPECT_EQ(twice.value().mesh.triangles, once.value().mesh.triangles);
}

TEST(Repair, T1FillsSmallHoles) {
  io::RawMesh m = test::torus(20, 5, 40, 20);
  m.triangles.erase(m.triangles.begin() + 100);
  m.triangles.erase(m.triangles.begin() + 100);  // a quad-shaped hole of 4 edges
  auto r = repair(m);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.holes_filled, 1u);
  EXPECT_EQ(r.value().report.hole_faces_added, 2u);
}

TEST(Repair, T1RefusesLargeHolesUnlessAllowed) {
  io::RawMesh m = test::torus(20, 5, 40, 20);
  for (int i = 0; i < 20; ++i) m.triangles.pop_back();
  RepairOptions options;
  options.max_hole_edges = 8;
  auto r = repair(m, options);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
  EXPECT_NE(r.error().message.find("hole"), std::string::npos);
  options.allow_open = true;
  auto open = repair(m, options);
  ASSERT_TRUE(open.ok());
  EXPECT_EQ(open.value().report.open_holes, 1u);
  EXPECT_FALSE(open.value().watertight);
}

TEST(Repair, T2SplitsNonManifoldEdge) {
  // Two cubes sharing the edge x=10, y=10 (z 0..10), as a soup (as STL delivers it).
  io::RawMesh m = test::soup(test::join(test::cube(), test::box({10, 10, 0}, {20, 20, 10})));
  auto r = repair(m);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.nonmanifold_edges, 1u);
  EXPECT_EQ(r.value().report.split_vertices, 2u);
  EXPECT_EQ(r.value().shells.size(), 2u);
  EXPECT_NEAR(signed_volume(r.value().mesh), 2000.0, 1e-9);
}

TEST(Repair, T2SplitsAVertexSharedByTwoFans) {
  // Two cubes touching at the corner (10, 10, 10) only: no edge has three faces, but the vertex
  // has two fans, so it is split.
  auto r = repair(test::soup(test::join(test::cube(), test::box({10, 10, 10}, {20, 20, 20}))));
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.nonmanifold_edges, 0u);
  EXPECT_EQ(r.value().report.split_vertices, 1u);
  EXPECT_EQ(r.value().shells.size(), 2u);
}

// Two tori with their faces interleaved, large enough that components are found in parallel: the
// same mesh and shells whatever the thread count, numbered as one pass in face order numbers them.
TEST(Repair, ComponentsOfALargeMeshDoNotDependOnTheThreadCount) {
  io::RawMesh a = test::torus(40, 15, 300, 150), b = test::torus(40, 15, 300, 150);
  for (auto& p : b.points) p = {p.x + 200.0, p.y, p.z * 0.5};
  const auto offset = static_cast<std::uint32_t>(a.points.size());
  io::RawMesh both;
  both.points = a.points;
  both.points.insert(both.points.end(), b.points.begin(), b.points.end());
  for (std::size_t f = 0; f < a.triangles.size(); ++f) {
    both.triangles.push_back(b.triangles[f]);
    for (auto& v : both.triangles.back()) v += offset;
    both.triangles.push_back(a.triangles[f]);
  }
  RepairedMesh first;
  for (int threads : {1, 4}) {
    tbb::task_arena arena(threads);
    auto r = arena.execute([&] { return repair(both); });
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_clean(r.value());
    ASSERT_EQ(r.value().shells.size(), 2u);
    EXPECT_GT(r.value().shells[0].volume_mm3, 1.9 * r.value().shells[1].volume_mm3);  // the full torus first
    EXPECT_EQ(r.value().report.flipped_faces, 0u);
    if (threads == 1) {
      first = r.value();
    } else {
      EXPECT_EQ(r.value().mesh.triangles, first.mesh.triangles);
      EXPECT_EQ(r.value().mesh.vertices, first.mesh.vertices);
    }
  }
}

TEST(Repair, T3FlipsFacesAndInvertedShells) {
  io::RawMesh m = test::cube();
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  auto r = repair(m);
  ASSERT_TRUE(r.ok());
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.flipped_faces, 1u);
  auto inside_out = repair(test::flipped(test::cube()));
  ASSERT_TRUE(inside_out.ok());
  expect_clean(inside_out.value());
  EXPECT_EQ(inside_out.value().report.inverted_shells, 1u);
  EXPECT_DOUBLE_EQ(signed_volume(inside_out.value().mesh), 1000.0);
}

TEST(Repair, T4RemovesDuplicateFaces) {
  io::RawMesh m = test::cube();
  m.triangles.push_back(m.triangles[5]);
  auto r = repair(m);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.duplicate_faces, 1u);
  EXPECT_EQ(r.value().mesh.triangles.size(), 12u);
}

TEST(Repair, T5RemovesDegenerateFaces) {
  io::RawMesh m = test::cube();
  m.triangles.push_back({0, 1, 1});
  m.points.push_back({5, 0, 0});  // on the edge 0-1
  m.triangles.push_back({0, 8, 1});
  auto r = repair(m);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.degenerate_faces, 2u);
}

// A cap, as meshers leave where an edge was split for a T-junction on one side only: the cube's
// edge 2-3 split at its middle on the side face, the gap closed by a face of zero area. The cap
// is flipped with the face across its long edge into two proper faces: nothing is removed, no
// hole is filled, and nothing crosses (removing it left a hole whose only fill was the cap again,
// which crossed its neighbours, and the decomposition refused such parts).
// The split point may lie off the edge by the rounding of an exported mesh (OpenSCAD's unions leave
// such caps 4 nm high, whose faces then cross): within the merge tolerance it is on the edge.
TEST(Repair, T5FlipsACapIntoProperFaces) {
  for (const auto& [at, off] : {std::pair{0.5, 0.0}, std::pair{0.2, 0.0}, std::pair{0.9, 0.0}, std::pair{0.5, 4e-6}, std::pair{0.3, -4e-6},
                               std::pair{0.7, 0.5 * core::kVertexMergeMm}}) {
    io::RawMesh m = test::cube();
    // The side face y = 10 is {2, 6, 7, 3}: triangles (2, 6, 7) and (2, 7, 3); edge 3-2 runs along x at z = 0.
    const auto mid = static_cast<std::uint32_t>(m.points.size());
    m.points.push_back({10.0 * at, 10 + off, 0});
    bool split = false;
    for (auto& t : m.triangles) {
      for (int k = 0; k < 3 && !split; ++k) {
        if (t[k] == 3 && t[(k + 1) % 3] == 2) {  // the side face's half-edge 3 -> 2
          const std::uint32_t x = t[(k + 2) % 3];
          t = {3, mid, x};
          m.triangles.push_back({mid, 2, x});
          split = true;
        }
      }
    }
    ASSERT_TRUE(split);
    m.triangles.push_back({2, mid, 3});  // the cap: 2 -> mid and mid -> 3 pair the split halves, 3 -> 2 the bottom's 2 -> 3
    RepairOptions o;
    o.check_self_intersections = true;
    auto r = repair(m, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_clean(r.value());
    EXPECT_EQ(r.value().report.flipped_caps, 1u) << at;
    EXPECT_EQ(r.value().report.degenerate_faces, 0u) << at;
    EXPECT_EQ(r.value().report.holes_filled, 0u) << at;
    EXPECT_EQ(r.value().report.self_intersecting_faces, 0u) << at;
    EXPECT_NEAR(signed_volume(r.value().mesh), 1000.0, 1e-9 + 20.0 * std::fabs(off)) << at;  // a sliver 10 x 10 x off/2 at most
  }
}

// A thin face whose vertex lies farther from its long edge than the merge tolerance is a face of
// the part, not a cap: it stays.
TEST(Repair, T5LeavesAThinFaceBeyondTheMergeTolerance) {
  io::RawMesh m = test::cube();
  const auto mid = static_cast<std::uint32_t>(m.points.size());
  m.points.push_back({5, 10 + 2.0 * core::kVertexMergeMm, 0});
  for (auto& t : m.triangles) {
    bool split = false;
    for (int k = 0; k < 3 && !split; ++k) {
      if (t[k] == 3 && t[(k + 1) % 3] == 2) {
        const std::uint32_t x = t[(k + 2) % 3];
        t = {3, mid, x};
        m.triangles.push_back({mid, 2, x});
        split = true;
      }
    }
    if (split) break;
  }
  m.triangles.push_back({2, mid, 3});
  auto r = repair(m);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.flipped_caps, 0u);
  EXPECT_EQ(r.value().mesh.triangles.size(), 14u);  // the cube's 12, the split and the thin face
}

// Two caps in a fan (the edge split twice on one side): the first cap looked at has the second
// across its long edge and can flip only after the second has.
TEST(Repair, T5FlipsAFanOfCaps) {
  io::RawMesh m = test::cube();
  const auto m1 = static_cast<std::uint32_t>(m.points.size());
  m.points.push_back({7, 10, 0});
  m.points.push_back({3, 10, 0});
  const std::uint32_t m2 = m1 + 1;
  bool split = false;
  for (auto& t : m.triangles) {
    for (int k = 0; k < 3 && !split; ++k) {
      if (t[k] == 3 && t[(k + 1) % 3] == 2) {  // the side face's half-edge 3 -> 2, now 3 -> m1 -> m2 -> 2
        const std::uint32_t x = t[(k + 2) % 3];
        t = {3, m1, x};
        m.triangles.push_back({m1, m2, x});
        m.triangles.push_back({m2, 2, x});
        split = true;
      }
    }
  }
  ASSERT_TRUE(split);
  m.triangles.push_back({m1, 2, m2});  // the inner cap, looked at first: its long edge m1-2 is the outer cap's
  m.triangles.push_back({3, 2, m1});   // the outer cap, across the bottom's edge 2-3
  RepairOptions o;
  o.check_self_intersections = true;
  auto r = repair(m, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.flipped_caps, 2u);
  EXPECT_EQ(r.value().report.degenerate_faces, 0u);
  EXPECT_EQ(r.value().report.self_intersecting_faces, 0u);
  EXPECT_NEAR(signed_volume(r.value().mesh), 1000.0, 1e-9);
}

// A fan of caps whose points were rounded off the edge by turns (an ASCII STL's six digits): each
// cap flips once, into faces that are no caps themselves (flips among points all near one line
// went round and round, thousands on a funnel of 1 136 faces), and nothing crosses.
TEST(Repair, T5FlipsAFanOfRoundedCapsOnceEach) {
  for (const int points : {3, 5}) {
    io::RawMesh m = test::cube();
    std::vector<std::uint32_t> on_edge;  // from 3 (x = 10) towards 2 (x = 0)
    for (int k = 1; k <= points; ++k) {
      on_edge.push_back(static_cast<std::uint32_t>(m.points.size()));
      m.points.push_back({10.0 - 10.0 * k / (points + 1), 10 + (k % 2 ? 3e-6 : -3e-6), 0});
    }
    bool split = false;
    for (std::size_t f = 0; f < m.triangles.size() && !split; ++f) {
      const auto t = m.triangles[f];
      for (int k = 0; k < 3 && !split; ++k) {
        if (t[k] == 3 && t[(k + 1) % 3] == 2) {  // the side face's half-edge 3 -> 2, now 3 -> p1 -> ... -> pn -> 2
          const std::uint32_t x = t[(k + 2) % 3];
          m.triangles[f] = {3, on_edge[0], x};
          for (std::size_t i = 0; i + 1 < on_edge.size(); ++i) m.triangles.push_back({on_edge[i], on_edge[i + 1], x});
          m.triangles.push_back({on_edge.back(), 2, x});
          split = true;
        }
      }
    }
    ASSERT_TRUE(split);
    // Caps in a fan from 2 closing the split side against the bottom's edge 2 -> 3.
    for (std::size_t i = 0; i + 1 < on_edge.size(); ++i) m.triangles.push_back({2, on_edge[i + 1], on_edge[i]});
    m.triangles.push_back({2, on_edge[0], 3});
    RepairOptions o;
    o.check_self_intersections = true;
    auto r = repair(m, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expect_clean(r.value());
    EXPECT_EQ(r.value().report.flipped_caps, static_cast<std::uint64_t>(points)) << points;
    EXPECT_EQ(r.value().report.self_intersecting_faces, 0u) << points;
    EXPECT_NEAR(signed_volume(r.value().mesh), 1000.0, 1e-3) << points;
  }
}

TEST(Repair, T6DetectsSelfIntersections) {
  io::RawMesh m = test::join(test::cube(), test::box({5, 5, 5}, {15, 15, 15}));
  auto r = repair(m);
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r.value().report.self_intersecting_faces, 0u);
  RepairOptions strict;
  strict.strict = true;
  auto s = repair(m, strict);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, core::ErrorCode::kInfeasible);
  auto clean = repair(test::torus(20, 5, 40, 20));
  EXPECT_EQ(clean.value().report.self_intersecting_faces, 0u);
}

TEST(Repair, T7SeparatesDisjointShells) {
  auto r = repair(test::join(test::cube(), test::box({20, 0, 0}, {25, 5, 5})));
  ASSERT_TRUE(r.ok());
  expect_clean(r.value());
  ASSERT_EQ(r.value().shells.size(), 2u);
  EXPECT_DOUBLE_EQ(r.value().shells[0].volume_mm3, 1000.0);
  EXPECT_DOUBLE_EQ(r.value().shells[1].volume_mm3, 125.0);
  EXPECT_TRUE(r.value().report.lines().empty());
}

TEST(Repair, T8InwardNestedShellIsACavity) {
  auto r = repair(test::join(test::cube(), test::flipped(test::box({2, 2, 2}, {8, 8, 8}))));
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().shells.size(), 2u);
  EXPECT_TRUE(r.value().shells[1].cavity);
  EXPECT_DOUBLE_EQ(signed_volume(r.value().mesh), 1000.0 - 216.0);
  EXPECT_EQ(r.value().report.interior_shells_removed, 0u);
}

TEST(Repair, T8OutwardNestedShellIsUnited) {
  auto r = repair(test::join(test::box({2, 2, 2}, {8, 8, 8}), test::cube()));
  ASSERT_TRUE(r.ok());
  expect_clean(r.value());
  ASSERT_EQ(r.value().shells.size(), 1u);
  EXPECT_EQ(r.value().report.interior_shells_removed, 1u);
  EXPECT_DOUBLE_EQ(signed_volume(r.value().mesh), 1000.0);
}

TEST(Repair, ClosedShellsThatOnlyTouchAreNotMerged) {
  // Two closed cubes with their own vertices meeting along an edge: nothing is open, so nothing
  // is merged; they stay two solids (slicing unites them).
  auto r = repair(test::join(test::cube(), test::box({10, 10, 0}, {20, 20, 10})));
  ASSERT_TRUE(r.ok());
  expect_clean(r.value());
  EXPECT_EQ(r.value().report.merged_vertices, 0u);
  EXPECT_EQ(r.value().shells.size(), 2u);
}

TEST(Repair, T9MergesNearCoincidentVertices) {
  io::RawMesh m = test::soup(test::cube());
  for (std::size_t i = 0; i < m.points.size(); ++i) m.points[i].x += static_cast<double>(i % 3) * 2e-5;  // within 1e-4
  auto r = repair(m);
  ASSERT_TRUE(r.ok()) << r.error().message;
  expect_clean(r.value());
  EXPECT_EQ(r.value().mesh.vertices.size(), 8u);
}

TEST(Repair, F7RefusesHugeCoordinates) {
  io::RawMesh m = test::cube();
  m.points[0].x = 2e6;
  auto r = repair(m);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
  EXPECT_NE(r.error().message.find("out of range"), std::string::npos);
}

TEST(Repair, F8WarnsAboutUnits) {
  io::RawMesh m = test::cube(0.05);  // 5 cm written in metres
  auto r = repair(m);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().warnings.size(), 1u);
  EXPECT_NE(r.value().warnings[0].find("--scale"), std::string::npos);
}

TEST(Repair, RefusesNonOrientableBand) {
  // A Möbius band of 8 quads closed with a half twist.
  io::RawMesh m;
  const int n = 8;
  for (int i = 0; i < n; ++i) {
    const double u = 2 * 3.14159265358979 * i / n;
    const double c = std::cos(u / 2);
    m.points.push_back({(10 + 2 * c) * std::cos(u), (10 + 2 * c) * std::sin(u), 2 * std::sin(u / 2)});
    m.points.push_back({(10 - 2 * c) * std::cos(u), (10 - 2 * c) * std::sin(u), -2 * std::sin(u / 2)});
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = 2 * i, b = 2 * i + 1;
    const std::uint32_t c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;
    m.triangles.push_back({a, b, d});
    m.triangles.push_back({a, d, c});
  }
  auto r = repair(m);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
}

TEST(Properties, OverhangOfAnLBlockArm) {
  // Column 20x20x60 with an arm 50x20x20 at z 40..60 reaching +X: the arm's underside (1000 mm²)
  // overhangs; the column's base rests on the plate.
  io::RawMesh m = test::join(test::box({0, 0, 0}, {20, 20, 60}), test::box({20, 0, 40}, {70, 20, 60}));
  Mesh mesh{m.points, m.triangles};
  const double rad30 = 30.0 * 3.14159265358979323846 / 180.0;
  // The joined faces at x = 20 are vertical and not overhangs.
  EXPECT_NEAR(overhang_area(mesh, {0, 0, 1}, rad30), 1000.0, 1e-9);
  // Built downwards from a plate at z = 60, nothing faces away from the build direction except
  // the top faces, which rest on the plate.
  EXPECT_NEAR(overhang_area(mesh, {0, 0, -1}, rad30), 0.0, 1e-9);
  // At a 60° self-supporting angle a 45° chamfer is fine, at 30° it overhangs.
  io::RawMesh wedge;
  wedge.points = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}, {0, 0, 10}, {0, 10, 10}};
  wedge.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {3, 5, 2}, {1, 2, 5}, {1, 5, 4}, {0, 4, 5}, {0, 5, 3}};
  Mesh w{wedge.points, wedge.triangles};
  EXPECT_NEAR(overhang_area(w, {1, 0, 0}, rad30), 0.0, 1e-9);  // the slope faces +x+z
  const double rad60 = 60.0 * 3.14159265358979323846 / 180.0;
  EXPECT_NEAR(overhang_area(w, {0, 0, -1}, rad60), 0.0, 1e-9);
  EXPECT_NEAR(overhang_area(w, {0, 0, -1}, rad30), 100.0 * std::sqrt(2.0), 1e-9);
}

}  // namespace
}  // namespace polyaxis::mesh
