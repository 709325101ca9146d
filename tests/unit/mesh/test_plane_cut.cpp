#include <gtest/gtest.h>

#include <optional>
#include <utility>

#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/self_intersections.h"
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

// A block with a post pushed through its top, as one mesh of two crossing shells: CGAL's clip is
// undefined where the plane meets faces that cross (a cut of two_branches through the seam of its
// union crashed in it). Such a plane is refused with an error; one that passes beside every crossing
// face cuts as usual.
TEST(PlaneCut, APlaneMeetingFacesThatCrossIsRefusedAndOneBesideThemCuts) {
  auto r = repair(test::join(test::cube(), test::box({4, 4, 8}, {6, 6, 14})));
  ASSERT_TRUE(r.ok());
  ASSERT_FALSE(r.value().self_intersecting.empty());
  const Mesh& m = r.value().mesh;
  auto take_first = [](const std::vector<Mesh>&) -> std::optional<std::size_t> { return 0; };
  for (const auto& [point, normal] : {std::pair{Vec3{0, 0, 9}, Vec3{0, 0, 1}}, std::pair{Vec3{5, 0, 0}, Vec3{1, 0, 0}},
                                      std::pair{Vec3{0, 0, 12}, Vec3{0.1, 0, 1}}}) {
    auto cut = cut_by_plane(m, point, normal);
    ASSERT_FALSE(cut.ok());
    EXPECT_EQ(cut.error().code, core::ErrorCode::kInfeasible);
    EXPECT_NE(cut.error().message.find("cross"), std::string::npos) << cut.error().message;
    auto off = cut_off(m, point, normal, take_first);
    ASSERT_FALSE(off.ok());
    EXPECT_EQ(off.error().code, core::ErrorCode::kInfeasible);
  }
  auto low = cut_by_plane(m, {0, 0, 3}, {0, 0, 1});
  ASSERT_TRUE(low.ok()) << low.error().message;
  expect_closed(low.value().below);
  EXPECT_NEAR(signed_volume(low.value().below), 300.0, 1e-9);
  auto off = cut_off(m, {0, 0, 3}, {0, 0, -1}, take_first);
  ASSERT_TRUE(off.ok()) << off.error().message;
  EXPECT_NEAR(signed_volume(off.value().child), 300.0, 1e-9);
}

TEST(PlaneCut, PlaneMissingThePart) {
  auto cut = cut_by_plane(solid(test::cube()), {0, 0, 50}, {0, 0, 1});
  ASSERT_TRUE(cut.ok());
  EXPECT_NEAR(signed_volume(cut.value().below), 1000.0, 1e-9);
  EXPECT_TRUE(cut.value().above.triangles.empty());
}

// A fork (a base with two prongs) cut across both prongs by a tilted plane: the child is the prong
// the picker takes; the other prong's tip goes back onto the parent, which is one solid (no shells
// touching along the cap) and can be cut again.
TEST(PlaneCut, CutOffPutsTheOtherPiecesBackAsOneSolid) {
  auto fork = unite({solid(test::box({0, 0, 0}, {30, 10, 10})), solid(test::box({0, 0, 5}, {10, 10, 40})),
                     solid(test::box({20, 0, 5}, {30, 10, 40}))});
  ASSERT_TRUE(fork.ok()) << fork.error().message;
  const Mesh& m = fork.value();
  expect_closed(m);
  std::size_t offered = 0;
  auto cut = cut_off(m, {0, 0, 25}, {0.1, 0.05, 1.0}, [&](const std::vector<Mesh>& pieces) -> std::optional<std::size_t> {
    offered = pieces.size();
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      if (bounding_box(pieces[i]).min.x > 15.0) return i;  // the +X prong
    }
    return std::nullopt;
  });
  ASSERT_TRUE(cut.ok()) << cut.error().message;
  EXPECT_EQ(offered, 2u);
  expect_closed(cut.value().child);
  expect_closed(cut.value().parent);
  EXPECT_NEAR(signed_volume(cut.value().child) + signed_volume(cut.value().parent), signed_volume(m), 1e-6 * signed_volume(m));
  EXPECT_EQ(cut.value().united_pieces, 0u);  // glued back along its cap
  auto again = repair(io::RawMesh{cut.value().parent.vertices, cut.value().parent.triangles});
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again.value().shells.size(), 1u);
  auto second = cut_by_plane(cut.value().parent, {0, 0, 20}, {-0.2, 0.1, 1.0});
  ASSERT_TRUE(second.ok()) << second.error().message;
  expect_closed(second.value().above);
  // Refusing every piece cuts nothing off.
  EXPECT_FALSE(cut_off(m, {0, 0, 25}, {0, 0, 1}, [](const std::vector<Mesh>&) { return std::optional<std::size_t>{}; }).ok());
}


// A coil (a square bar on a helix) cut by a plane through its axis: the far side falls into one
// piece a turn. The child is one; the others are glued back onto the near side along their caps,
// each cap's edges split where the other side's clip put points of its own on the cut line (the
// corefinement it replaces took seconds on a wire spring), and the parent is one closed solid
// holding exactly the rest. Other coil sizes, turns, tessellations and plane tilts.
TEST(PlaneCut, CutOffGluesTheOtherPiecesOfACoilBackOntoTheParent) {
  struct Coil {
    double w, r, turns, h, step;
    core::Vec3 normal;
  };
  for (const Coil& c : {Coil{3, 12, 2.5, 30, 0.5, {1, 0, 0}}, Coil{2, 9, 3.5, 40, 0.8, {1, 0.3, 0.1}}, Coil{4, 15, 2.2, 25, 0.35, {0.8, -0.6, -0.05}}}) {
    SCOPED_TRACE(c.r);
    const Mesh coil = solid(test::helical_bar(c.w, c.r, c.turns, c.h, c.step));
    std::size_t offered = 0;
    auto cut = cut_off(coil, {0, 0, 0}, c.normal, [&](const std::vector<Mesh>& pieces) -> std::optional<std::size_t> {
      offered = pieces.size();
      return 0;
    });
    ASSERT_TRUE(cut.ok()) << cut.error().message;
    EXPECT_GE(offered, 2u);
    EXPECT_EQ(cut.value().united_pieces, 0u);
    expect_closed(cut.value().child);
    expect_closed(cut.value().parent);
    const double whole = signed_volume(coil);
    EXPECT_NEAR(signed_volume(cut.value().child) + signed_volume(cut.value().parent), whole, 1e-9 * whole);
    auto again = repair(io::RawMesh{cut.value().parent.vertices, cut.value().parent.triangles});
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again.value().shells.size(), 1u);
    EXPECT_TRUE(self_intersecting_faces(cut.value().parent).empty());
  }
}

// A cavity wholly on the far side goes with the piece around it (the child here), not the parent.
TEST(PlaneCut, CutOffKeepsACavityWithThePieceAroundIt) {
  auto hollow = repair(test::join(test::box({0, 0, 0}, {20, 20, 20}), test::flipped(test::box({12, 6, 6}, {16, 10, 10}))));
  ASSERT_TRUE(hollow.ok());
  auto cut = cut_off(hollow.value().mesh, {10, 0, 0}, {1, 0, 0}, [](const std::vector<Mesh>& pieces) -> std::optional<std::size_t> {
    return pieces.size() == 1 ? std::optional<std::size_t>{0} : std::nullopt;  // the cavity is not offered
  });
  ASSERT_TRUE(cut.ok()) << cut.error().message;
  EXPECT_NEAR(signed_volume(cut.value().child), 10.0 * 20.0 * 20.0 - 64.0, 1e-9);
  EXPECT_NEAR(signed_volume(cut.value().parent), 10.0 * 20.0 * 20.0, 1e-9);
}

TEST(Difference, OverlapDisjointAndContained) {
  using test::box;
  // A block less a slab across its lower part: the upper part, closed.
  const auto upper = difference(solid(box({0, 0, 0}, {10, 20, 30})), solid(box({-5, -5, -1}, {15, 25, 12})));
  ASSERT_TRUE(upper.ok()) << upper.error().message;
  expect_closed(upper.value());
  EXPECT_NEAR(signed_volume(upper.value()), 10.0 * 20.0 * 18.0, 1e-6);
  // A boss sunk into a dome: what stands out of it, less than the boss.
  const Mesh boss = solid(test::cylinder({0, 0, 10}, {0, 0, 1}, 5, 15, 40));
  const auto out = difference(boss, solid(test::spherical_cap(40, 20, 64, 16)));
  ASSERT_TRUE(out.ok()) << out.error().message;
  expect_closed(out.value());
  EXPECT_GT(signed_volume(out.value()), 0.3 * signed_volume(boss));
  EXPECT_LT(signed_volume(out.value()), 0.7 * signed_volume(boss));
  // Apart: A itself; inside B: nothing.
  const auto apart = difference(solid(box({0, 0, 0}, {4, 4, 4})), solid(box({10, 0, 0}, {14, 4, 4})));
  ASSERT_TRUE(apart.ok());
  EXPECT_NEAR(signed_volume(apart.value()), 64.0, 1e-9);
  const auto inside = difference(solid(box({1, 1, 1}, {3, 3, 3})), solid(box({0, 0, 0}, {4, 4, 4})));
  ASSERT_TRUE(inside.ok());
  EXPECT_TRUE(inside.value().triangles.empty());
}

TEST(Intersection, OverlapDisjointAndContained) {
  using test::box;
  // A block and a slab across its lower part: their common slab, closed; with the difference, the block.
  const Mesh block = solid(box({0, 0, 0}, {10, 20, 30})), slab = solid(box({-5, -5, -1}, {15, 25, 12}));
  const auto lower = intersection(block, slab);
  ASSERT_TRUE(lower.ok()) << lower.error().message;
  expect_closed(lower.value());
  EXPECT_NEAR(signed_volume(lower.value()), 10.0 * 20.0 * 12.0, 1e-6);
  const auto upper = difference(block, slab);
  ASSERT_TRUE(upper.ok());
  EXPECT_NEAR(signed_volume(lower.value()) + signed_volume(upper.value()), signed_volume(block), 1e-6);
  // Apart: nothing; inside: the inner one.
  const auto apart = intersection(solid(box({0, 0, 0}, {4, 4, 4})), solid(box({10, 0, 0}, {14, 4, 4})));
  ASSERT_TRUE(apart.ok());
  EXPECT_TRUE(apart.value().triangles.empty());
  const auto inside = intersection(solid(box({1, 1, 1}, {3, 3, 3})), solid(box({0, 0, 0}, {4, 4, 4})));
  ASSERT_TRUE(inside.ok());
  EXPECT_NEAR(signed_volume(inside.value()), 8.0, 1e-9);
}

TEST(Grown, MovesSmoothSurfacesByTheOffsetAndCornersAlongTheirMeanNormal) {
  // A fine cylinder's side moves out by the offset (its radius grows by it, to the faceting).
  const Mesh bar = solid(test::cylinder({0, 0, 0}, {0, 0, 1}, 10, 20, 96));
  const Mesh fat = grown(bar, 0.05);
  ASSERT_EQ(fat.vertices.size(), bar.vertices.size());
  for (const core::Vec3& v : fat.vertices) {
    if (v.z > 0.0 && v.z < 20.0) continue;  // no vertex lies between the caps
    const double r = std::hypot(v.x, v.y);
    if (r > 1.0) {
      EXPECT_GT(r, 10.0) << r;  // the rim: out along the mean of side and cap
    }
  }
  const double side = 2.0 * M_PI * 10.0 * 20.0, caps = 2.0 * M_PI * 100.0;
  EXPECT_GT(signed_volume(fat) - signed_volume(bar), 0.5 * 0.05 * (side + caps));
  EXPECT_LT(signed_volume(fat) - signed_volume(bar), 1.01 * 0.05 * (side + caps));
  // A cube's corners go out along their diagonal, its faces by the offset over √3; inwards too.
  const Mesh cube = solid(test::box({0, 0, 0}, {10, 10, 10}));
  const Mesh big = grown(cube, 0.3), small = grown(cube, -0.3);
  const double f = 0.3 / std::sqrt(3.0);
  EXPECT_NEAR(signed_volume(big), std::pow(10.0 + 2.0 * f, 3), 1e-9);
  EXPECT_NEAR(signed_volume(small), std::pow(10.0 - 2.0 * f, 3), 1e-9);
  // Its use: a solid less a copy of itself grown a little leaves nothing, the same copy not grown
  // leaves nothing either; one retriangulated and rounded to floats can leave slivers.
  const auto none = difference(cube, grown(cube, 1e-3));
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none.value().triangles.empty());
}

// A union's surface with slivers along its seam (OpenSCAD's union of a 64-sided trunk and a
// 48-sided tube), cut below a plane and grown a little, crosses itself along the seam; its outer
// surface does not, and holds the grown solid. The part less it finishes (with the cut as given,
// whose faces lie on the part's, CGAL's corefinement ran for minutes or refused), and leaves what
// stands above the cut. Cut at several heights through the seam and the arms.
TEST(WithoutCrossings, AGrownUnionFoldedAlongItsSeamGetsItsOuterSurface) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/two_branches.stl");
  ASSERT_TRUE(read.ok());
  // As read, caps and all: repair now flips the seam's caps, 4 nm off their edges, after which
  // the grown cut no longer folds (merge_mm 0 leaves them, as before).
  RepairOptions as_read;
  as_read.merge_mm = 0.0;
  auto repaired = repair(read.value().mesh, as_read);
  ASSERT_TRUE(repaired.ok());
  const Mesh part = repaired.value().mesh;
  const double whole = signed_volume(part);
  for (const double z : {35.0, 40.0, 50.0}) {
    SCOPED_TRACE(z);
    auto cut = cut_by_plane(part, {0, 0, z}, {0, 0, 1});
    ASSERT_TRUE(cut.ok());
    const Mesh& below = cut.value().below;
    const Mesh skin = grown(below, 0.02);
    ASSERT_FALSE(self_intersecting_faces(skin).empty());  // the case at hand
    auto outer = without_crossings(skin);
    ASSERT_TRUE(outer.ok()) << outer.error().message;
    expect_closed(outer.value());
    EXPECT_TRUE(self_intersecting_faces(outer.value()).empty());
    const double v = signed_volume(below), area = surface_area(below);
    EXPECT_GT(signed_volume(outer.value()), v + 0.5 * 0.02 * area);
    EXPECT_LT(signed_volume(outer.value()), v + 1.01 * 0.02 * area);
    auto rest = difference(part, outer.value());
    ASSERT_TRUE(rest.ok()) << rest.error().message;
    expect_closed(rest.value());
    EXPECT_LT(signed_volume(rest.value()), whole - v);  // what stands above the cut, less the skin over the cap
    EXPECT_GT(signed_volume(rest.value()), whole - v - 0.02 * area);
  }
  // A surface that crosses nothing is itself.
  const Mesh cube = solid(test::box({0, 0, 0}, {10, 10, 10}));
  auto same = without_crossings(cube);
  ASSERT_TRUE(same.ok());
  EXPECT_NEAR(signed_volume(same.value()), 1000.0, 1e-9);
}

}  // namespace
}  // namespace polyaxis::mesh
