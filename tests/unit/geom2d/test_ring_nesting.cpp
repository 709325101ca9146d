// union_rings without Clipper where the rings need no boolean (geom2d/ring_nesting.h): wherever the
// shortcut answers, its polygons are Clipper's point for point; it answers for nested rings turned
// by their depth (and for every union's own output), and leaves crossing, touching, collinear and
// wrongly turned rings to Clipper.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geom2d/ring_nesting.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/load_part.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::geom2d {
namespace {

bool same(const std::vector<Polygon>& a, const std::vector<Polygon>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].outer != b[i].outer || a[i].holes != b[i].holes) return false;
  }
  return true;
}

// A star-shaped ring about (CX, CY): N points at random radii in [R0, R1], turned as CCW asks.
Ring star(std::mt19937& rng, double cx, double cy, double r0, double r1, int n, bool ccw) {
  std::uniform_real_distribution<double> r(r0, r1), jitter(-0.3, 0.3);
  Ring ring;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * (k + 0.5 + jitter(rng)) / n, rad = r(rng);
    ring.push_back({to_units(cx + rad * std::cos(a)), to_units(cy + rad * std::sin(a))});
  }
  if (!ccw) std::reverse(ring.begin(), ring.end());
  return ring;
}

// Compares the shortcut with Clipper on RINGS under both fill rules; true when the shortcut answered.
bool check(const std::vector<Ring>& rings) {
  const auto nested = detail::union_of_nested_rings(rings);
  for (const FillRule rule : {FillRule::kNonZero, FillRule::kEvenOdd}) {
    const auto clipper = detail::union_rings_by_clipper(rings, rule);
    if (nested) {
      EXPECT_TRUE(same(*nested, clipper)) << "the shortcut's polygons differ from Clipper's";
    }
    EXPECT_TRUE(same(union_rings(rings, rule), clipper));
  }
  return nested.has_value();
}

TEST(RingNesting, NestedStarsAreClippersPolygons) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> points(3, 200);
  std::size_t answered = 0;
  for (int t = 0; t < 400; ++t) {
    // Islands in holes in discs, side by side; every ring turned by its depth.
    std::vector<Ring> rings;
    for (int k = 0; k < 1 + t % 4; ++k) {
      const double cx = 100.0 * k;
      rings.push_back(star(rng, cx, 0, 30, 40, points(rng), true));
      if (t % 2) rings.push_back(star(rng, cx, 0, 15, 25, points(rng), false));
      if (t % 2 && t % 3 == 0) rings.push_back(star(rng, cx, 0, 5, 10, points(rng), true));
    }
    std::shuffle(rings.begin(), rings.end(), rng);
    answered += check(rings) ? 1 : 0;
  }
  EXPECT_GT(answered, 390u);  // not vacuous: the shortcut answers for these
}

TEST(RingNesting, LeavesWhatNeedsABooleanToClipper) {
  std::mt19937 rng(8);
  for (int t = 0; t < 200; ++t) {
    const int n = 8 + t % 50;
    // Overlapping discs, a hole turned the wrong way, a disc inside a disc both CCW, discs touching.
    const std::vector<Ring> overlap = {star(rng, 0, 0, 30, 40, n, true), star(rng, 50, 0, 30, 40, n, true)};
    const std::vector<Ring> wrong_hole = {star(rng, 0, 0, 30, 40, n, true), star(rng, 0, 0, 10, 20, n, true)};
    Ring a = star(rng, 0, 0, 30, 40, n, true), b = a;
    for (Point& p : b) p.x += to_units(100.0);
    b.front() = a.front();  // a shared point
    const std::vector<Ring> touching = {a, b};
    EXPECT_FALSE(check(overlap));
    EXPECT_FALSE(check(wrong_hole));
    EXPECT_FALSE(check(touching));
  }
  // Collinear points (Clipper drops them) and a self-crossing bow tie.
  const Ring square = {{0, 0}, {5, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_FALSE(check({square}));
  const Ring bow = {{0, 0}, {10, 10}, {10, 0}, {0, 10}};
  EXPECT_FALSE(check({bow}));
  // Many rings in one another's boxes: the shortcut gives up rather than test every pair.
  std::vector<Ring> many;
  for (int k = 0; k < 3000; ++k) many.push_back(star(rng, 0.0, 0.0, 1000.0 + k, 1000.5 + k, 3, k % 2 == 0));
  EXPECT_FALSE(detail::union_of_nested_rings(many).has_value());
}

TEST(RingNesting, SectionsOfMeshesAreClippersPolygons) {
  std::size_t answered = 0, layers = 0;
  for (const char* name : {"two_branches.stl", "cyl_walls5.stl", "impeller.stl", "hinge.stl", "dome_sphere.stl"}) {
    mesh::LoadOptions lo;
    lo.path = std::string(POLYAXIS_EXAMPLES_DIR) + "/parts/" + name;
    auto part = mesh::load_part(lo);
    ASSERT_TRUE(part) << name;
    for (const core::Vec3 d : {core::Vec3{0, 0, 1}, core::normalized(core::Vec3{0.3, -0.2, 1.0}), core::normalized(core::Vec3{1, 1, 0.2})}) {
      slicing::SliceOptions o;
      o.direction = d;
      o.layer_mm = 0.7;
      auto sliced = slicing::slice(part.value().repaired.mesh, o);
      ASSERT_TRUE(sliced);
      for (const slicing::Layer& l : sliced.value().layers) {
        ++layers;
        answered += check(rings_of(l.polygons)) ? 1 : 0;
      }
    }
  }
  // A union's own polygons need no boolean again: the shortcut takes every one.
  EXPECT_EQ(answered, layers);
}

}  // namespace
}  // namespace polyaxis::geom2d
