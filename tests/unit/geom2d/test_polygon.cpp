#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::geom2d {
namespace {

Ring square(std::int64_t x0, std::int64_t y0, std::int64_t s) { return {{x0, y0}, {x0 + s, y0}, {x0 + s, y0 + s}, {x0, y0 + s}}; }

TEST(Polygon, ExactAreaAndOrientation) {
  const Ring r = square(0, 0, to_units(10));
  EXPECT_EQ(twice_signed_area(r), static_cast<Int128>(2) * to_units(10) * to_units(10));
  EXPECT_DOUBLE_EQ(signed_area_mm2(r), 100.0);
  EXPECT_EQ(orientation({0, 0}, {1, 0}, {0, 1}), 1);
  EXPECT_EQ(orientation({0, 0}, {1, 1}, {2, 2}), 0);
  // Far coordinates: the 128-bit product does not overflow.
  const std::int64_t big = to_units(1e6);
  EXPECT_EQ(orientation({-big, -big}, {big, -big}, {big, big}), 1);
}

TEST(Polygon, Simplicity) {
  EXPECT_TRUE(is_simple(square(0, 0, 10)));
  EXPECT_FALSE(is_simple({{0, 0}, {10, 10}, {10, 0}, {0, 10}}));  // bow tie
  EXPECT_FALSE(is_simple({{0, 0}, {10, 0}, {10, 0}, {0, 10}}));   // repeated point
}

// A point's distance (mm) from the closed ring R.
double distance_to_ring_mm(Point p, const Ring& r) {
  double best = INFINITY;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Point a = r[i], b = r[(i + 1) % r.size()];
    const double ux = double(b.x - a.x), uy = double(b.y - a.y), px = double(p.x - a.x), py = double(p.y - a.y);
    const double l2 = ux * ux + uy * uy, t = l2 > 0 ? std::clamp((px * ux + py * uy) / l2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(px - t * ux, py - t * uy));
  }
  return best / kUnitsPerMm;
}

TEST(Polygon, SimplifiedDropsOnlyPointsWithinTheTolerance) {
  // Circles of several radii and point counts, with a point half-way along every edge nudged off
  // it by less than the tolerance (the diagonal of a split quad): those go, the corners stay.
  for (const double radius : {0.7, 5.0, 55.0}) {
    for (const int n : {12, 97, 640}) {
      Ring ring;
      for (int k = 0; k < n; ++k) {
        const double a0 = 2 * 3.14159265358979 * k / n, a1 = 2 * 3.14159265358979 * (k + 0.5) / n;
        ring.push_back({to_units(radius * std::cos(a0)), to_units(radius * std::sin(a0))});
        const double r_mid = radius * std::cos(3.14159265358979 / n) - 0.0005;  // just inside the chord
        ring.push_back({to_units(r_mid * std::cos(a1)), to_units(r_mid * std::sin(a1))});
      }
      for (const double tol : {0.001, 0.002, 0.01}) {
        const Ring s = simplified(ring, tol);
        ASSERT_GE(s.size(), 3u);
        EXPECT_LE(s.size(), ring.size());
        for (const Point& p : ring) EXPECT_LE(distance_to_ring_mm(p, s), tol + 1e-9) << radius << " " << n << " " << tol;
        for (const Point& p : s) EXPECT_NE(std::find(ring.begin(), ring.end(), p), ring.end());  // a subset, in order
        EXPECT_LE(s.size(), static_cast<std::size_t>(n)) << "the nudged mid-points go";
        EXPECT_TRUE(is_simple(s));
      }
    }
  }
  // A square keeps its corners, with or without points along its sides.
  const std::int64_t mm = to_units(1);
  const Ring sq{{0, 0}, {5 * mm, 0}, {10 * mm, 0}, {10 * mm, 10 * mm}, {0, 10 * mm}, {0, 4 * mm}};
  EXPECT_EQ(simplified(sq, 0.002), (Ring{{0, 0}, {10 * mm, 0}, {10 * mm, 10 * mm}, {0, 10 * mm}}));
  // Too few points to keep, or no tolerance: as it is.
  const Ring thin{{0, 0}, {10 * mm, 0}, {10 * mm, 1000}, {0, 1000}};
  EXPECT_EQ(simplified(thin, 0.002), thin);
  EXPECT_EQ(simplified(sq, 0.0), sq);
}

TEST(Clip, UnionNestsHolesAndOrients) {
  const std::int64_t mm = to_units(1);
  Ring hole = square(2 * mm, 2 * mm, 6 * mm);
  const auto polys = union_rings({square(0, 0, 10 * mm), hole}, FillRule::kEvenOdd);
  ASSERT_EQ(polys.size(), 1u);
  ASSERT_EQ(polys[0].holes.size(), 1u);
  EXPECT_GT(twice_signed_area(polys[0].outer), 0);
  EXPECT_LT(twice_signed_area(polys[0].holes[0]), 0);
  EXPECT_DOUBLE_EQ(area_mm2(polys[0]), 100.0 - 36.0);
}

TEST(Clip, NonZeroUnionOfOverlaps) {
  const std::int64_t mm = to_units(1);
  const auto polys = union_rings({square(0, 0, 10 * mm), square(5 * mm, 5 * mm, 10 * mm)}, FillRule::kNonZero);
  ASSERT_EQ(polys.size(), 1u);
  EXPECT_DOUBLE_EQ(area_mm2(polys[0]), 175.0);
}

// Rings that touch at a vertex come out as simple rings that share the vertex, never as one ring
// through it twice (the strictly-simple pass runs when the plain union leaves a repeated vertex).
TEST(Clip, UnionOfRingsTouchingAtAVertexGivesSimpleRings) {
  const std::int64_t mm = to_units(1);
  // Two squares corner to corner, as two rings and as one ring through the corner twice (which
  // Clipper's plain union hands back as it is); a hole whose corner lies on the outer ring.
  const Ring hole = {{10 * mm, 0}, {5 * mm, 5 * mm}, {10 * mm, 10 * mm}, {15 * mm, 5 * mm}};
  const Ring figure_eight = {{0, 0}, {10 * mm, 0}, {10 * mm, 10 * mm}, {20 * mm, 10 * mm}, {20 * mm, 20 * mm}, {10 * mm, 20 * mm}, {10 * mm, 10 * mm}, {0, 10 * mm}};
  const std::vector<std::pair<std::vector<Ring>, double>> cases = {
      {{square(0, 0, 20 * mm), hole}, 400.0 - 50.0},
      {{square(0, 0, 10 * mm), square(10 * mm, 10 * mm, 10 * mm)}, 200.0},
      {{figure_eight}, 200.0},
  };
  for (const auto& [rings, want] : cases) {
    const auto polys = union_rings(rings, FillRule::kNonZero);
    double area = 0.0;
    for (const Polygon& p : polys) {
      EXPECT_TRUE(is_simple(p.outer));
      for (const Ring& h : p.holes) EXPECT_TRUE(is_simple(h));
      area += area_mm2(p);
    }
    EXPECT_NEAR(area, want, 1e-9);
  }
}

TEST(Clip, OffsetShrinksASquare) {
  const std::int64_t mm = to_units(1);
  const auto polys = offset({Polygon{square(0, 0, 10 * mm), {}}}, -1.0);
  ASSERT_EQ(polys.size(), 1u);
  EXPECT_NEAR(area_mm2(polys[0]), 64.0, 1e-9);
}

// The union's boundary, not nested: the same area as the nested union, and grown the same, for
// sections of neighbouring regions that share edges, a frame around a hole with a region in it,
// and rings that nest already (handed back as they are).
TEST(Clip, UnionBoundaryCoversWhatTheUnionDoesAndGrowsAlike) {
  const std::int64_t mm = to_units(1);
  const Ring frame_hole = {{2 * mm, 8 * mm}, {8 * mm, 8 * mm}, {8 * mm, 2 * mm}, {2 * mm, 2 * mm}};  // clockwise
  const std::vector<std::vector<Ring>> cases = {
      {square(0, 0, 10 * mm), square(10 * mm, 0, 10 * mm), square(0, 10 * mm, 20 * mm)},
      {square(0, 0, 10 * mm), frame_hole, square(4 * mm, 4 * mm, 2 * mm), square(10 * mm, 3 * mm, 4 * mm)},
      {square(0, 0, 10 * mm), frame_hole},
  };
  auto area = [](const std::vector<Polygon>& polys) {
    double a = 0.0;
    for (const Polygon& p : polys) a += area_mm2(p);
    return a;
  };
  for (const auto& rings : cases) {
    const auto nested = union_rings(rings, FillRule::kNonZero);
    const auto boundary = union_boundary(rings, FillRule::kNonZero);
    double signed_area = 0.0;
    for (const Ring& r : boundary) signed_area += static_cast<double>(twice_signed_area(r)) / 2.0;
    EXPECT_NEAR(signed_area / static_cast<double>(mm) / static_cast<double>(mm), area(nested), 1e-9);
    for (const double grow : {0.3, 1.5}) EXPECT_NEAR(area(offset_rings(boundary, grow)), area(offset(nested, grow)), 1e-9) << grow;
  }
}

TEST(Clip, SweepOfAnOpenLineIsAStadium) {
  const std::int64_t mm = to_units(1);
  const auto polys = sweep_open({Ring{{0, 0}, {10 * mm, 0}}}, 1.0);
  ASSERT_EQ(polys.size(), 1u);
  EXPECT_NEAR(area_mm2(polys[0]), 20.0 + 3.14159265358979, 0.01);  // the round ends within 2 µm
  EXPECT_TRUE(sweep_open({}, 1.0).empty());
}

TEST(Clip, ClipOpenKeepsThePartsInside) {
  const std::int64_t mm = to_units(1);
  // A line across a square with a hole: the two pieces between the square's sides and the hole's.
  const Ring outer = square(0, 0, 10 * mm), hole = square(4 * mm, 4 * mm, 2 * mm);
  Ring hole_cw(hole.rbegin(), hole.rend());
  const auto parts = clip_open({Ring{{-5 * mm, 5 * mm}, {15 * mm, 5 * mm}}}, {outer, hole_cw});
  ASSERT_EQ(parts.size(), 2u);
  double length = 0.0;
  for (const Ring& r : parts) {
    ASSERT_EQ(r.size(), 2u);
    length += std::abs(to_mm(r[1].x - r[0].x));
    for (const Point& q : r) EXPECT_EQ(q.y, 5 * mm);
  }
  EXPECT_NEAR(length, 8.0, 1e-9);
}

}  // namespace
}  // namespace polyaxis::geom2d
