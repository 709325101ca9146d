// Centre lines of thin pieces (toolpath/gap_fill.cpp): on arcs, wedges and jagged pieces of many
// vertices, inside the piece, at least the asked width from its boundary; a closed loop round a
// tube's section; nothing for pieces too narrow, with two holes or degenerate.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>

#include "polyaxis/geom2d/clip.h"
#include "toolpath/gap_fill.h"

namespace polyaxis::toolpath::detail {
namespace {

using geom2d::Point;
using geom2d::Polygon;
using geom2d::Ring;

constexpr double kPi = 3.14159265358979323846;

Point mm(double x, double y) { return {geom2d::to_units(x), geom2d::to_units(y)}; }

// An annular sector between radii R and R + W over ANGLE_DEG, N points a side (counter-clockwise).
Polygon arc(double r, double w, double angle_deg, int n) {
  Polygon p;
  const double a = angle_deg * kPi / 180.0;
  for (int i = 0; i <= n; ++i) p.outer.push_back(mm((r + w) * std::cos(a * i / n), (r + w) * std::sin(a * i / n)));
  for (int i = n; i >= 0; --i) p.outer.push_back(mm(r * std::cos(a * i / n), r * std::sin(a * i / n)));
  return p;
}

double length_mm(const Ring& line) {
  double l = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) l += std::hypot(geom2d::to_mm(line[i].x - line[i - 1].x), geom2d::to_mm(line[i].y - line[i - 1].y));
  return l;
}

TEST(GapFill, ArcsOfManyVerticesGetOneLineAlongTheirMiddle) {
  for (const int n : {8, 200, 1500}) {
    for (const double w : {0.5, 0.8}) {
      const Polygon piece = arc(20.0, w, 60.0, n);
      const auto t0 = std::chrono::steady_clock::now();
      const auto lines = centre_lines(piece, 0.9, 0.45);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ASSERT_EQ(lines.size(), 1u) << n << " " << w;
      // Along the middle radius (within the polygon's sag from the arc, and the 0.01 mm the outline
      // is simplified by), nearly the whole arc long.
      const double sag = 20.0 * (1.0 - std::cos(kPi / 3.0 / n / 2.0));
      for (const Point& q : lines[0]) EXPECT_NEAR(std::hypot(geom2d::to_mm(q.x), geom2d::to_mm(q.y)), 20.0 + w / 2.0, sag + 0.03) << n;
      EXPECT_GT(length_mm(lines[0]), (20.0 + w / 2.0) * kPi / 3.0 - 2.0 * w) << n;
      EXPECT_LT(seconds, 60.0);  // not a timing assertion: a guard against a hang
      // Narrower than the asked width: nothing.
      EXPECT_TRUE(centre_lines(piece, 0.9, 2.0 * w).empty());
    }
  }
}

TEST(GapFill, LinesStayInsideAndClearOfTheBoundary) {
  // Wedges and jagged slivers at random: every point of a line is inside the piece and at least
  // half the asked width from its boundary, less the 0.01 mm the outline is simplified by.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int with_lines = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Polygon piece;
    const int n = 3 + static_cast<int>(u(rng) * 40);
    const double length = 2.0 + 20.0 * u(rng), width = 0.3 + 1.2 * u(rng);
    for (int i = 0; i <= n; ++i) piece.outer.push_back(mm(length * i / n, width * (0.5 + 0.5 * u(rng))));
    for (int i = n; i >= 0; --i) piece.outer.push_back(mm(length * i / n, -width * (0.5 + 0.5 * u(rng)) * (trial % 3 == 0 ? 0.0 : 1.0) - 1e-3));
    const double min_width = 0.45;
    const auto lines = centre_lines(piece, 0.9, min_width);
    with_lines += lines.empty() ? 0 : 1;
    const auto inner = geom2d::offset({piece}, -(min_width / 2.0 - 0.0101));
    for (const Ring& line : lines) {
      EXPECT_GE(length_mm(line), 0.25 * 0.9 - 1e-6);
      EXPECT_TRUE(geom2d::clip_open({line}, geom2d::rings_of(inner)).size() == 1u) << trial;
    }
  }
  EXPECT_GT(with_lines, 50);
}

// A ring between radii R and R + W (N sides each way), counter-clockwise outside, clockwise hole,
// the hole's centre moved by SHIFT in x.
Polygon tube(double r, double w, int n, double shift = 0.0) {
  Polygon p;
  for (int i = 0; i < n; ++i) p.outer.push_back(mm((r + w) * std::cos(2 * kPi * i / n), (r + w) * std::sin(2 * kPi * i / n)));
  Ring hole;
  for (int i = n - 1; i >= 0; --i) hole.push_back(mm(shift + r * std::cos(2 * kPi * i / n), r * std::sin(2 * kPi * i / n)));
  p.holes.push_back(hole);
  return p;
}

TEST(GapFill, ATubesSectionGetsOneClosedLoopRoundItsHole) {
  // Walls of w·cos(π/n) across, 0.5 mm and more.
  for (const int n : {8, 64, 400}) {
    for (const double w : {0.55, 0.8}) {
      const auto lines = centre_lines(tube(15.0, w, n), 0.9, 0.45);
      ASSERT_EQ(lines.size(), 1u) << n << " " << w;
      EXPECT_EQ(lines[0].front(), lines[0].back());  // closed
      const double sag = (15.0 + w) * (1.0 - std::cos(kPi / n));
      for (const Point& q : lines[0]) {
        const double rq = std::hypot(geom2d::to_mm(q.x), geom2d::to_mm(q.y));
        EXPECT_GT(rq, 15.0 - sag - 0.01) << n;
        EXPECT_LT(rq, 15.0 + w + 0.01) << n;
      }
      // Round the whole ring: about the middle circle's length (the polygon's, for few sides).
      EXPECT_NEAR(length_mm(lines[0]), 2.0 * n * (15.0 + w / 2.0) * std::sin(kPi / n), 0.05 * w * n + 0.2) << n << " " << w;
    }
  }
  EXPECT_TRUE(centre_lines(tube(15.0, 0.3, 64), 0.9, 0.45).empty());  // narrower than asked all round
  // The hole moved off centre: the wall runs from 0.2 to 1.4 mm; the line keeps to the wide side.
  const auto open = centre_lines(tube(15.0, 0.8, 128, 0.6), 0.9, 0.45);
  ASSERT_EQ(open.size(), 1u);
  EXPECT_NE(open[0].front(), open[0].back());
  for (const Point& q : open[0]) EXPECT_LT(geom2d::to_mm(q.x), 15.0);
}

TEST(GapFill, NothingForTwoHolesOrDegeneratePieces) {
  Polygon two = tube(15.0, 0.8, 64);
  two.holes.push_back(tube(2.0, 0.5, 16).holes[0]);  // a second hole, inside the first: not a valid piece
  EXPECT_TRUE(centre_lines(two, 0.9, 0.45).empty());
  EXPECT_TRUE(centre_lines(Polygon{{mm(0, 0), mm(1, 0), mm(2, 0)}, {}}, 0.9, 0.45).empty());  // collinear
  EXPECT_TRUE(centre_lines(Polygon{{mm(0, 0), mm(1, 0)}, {}}, 0.9, 0.45).empty());
  EXPECT_TRUE(centre_lines(Polygon{{mm(0, 0), mm(5, 0), mm(5, 1), mm(0, 1), mm(0, 0), mm(5, 1)}, {}}, 0.9, 0.45).empty());  // crossing
}

}  // namespace
}  // namespace polyaxis::toolpath::detail
