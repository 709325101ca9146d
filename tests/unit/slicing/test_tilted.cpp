// Tilted "3-D" layers (issue 13, item 1; Ruan §4.2.2): on bars bent through various angles, at
// several tessellations, the planes follow the bar, every thickness (measured here from the
// corners of each section to the previous plane, along the layer's normal) stays in range, the
// sections stay closed and simple, and each section stands on the one below within the overhang
// limit; on a straight bar the planes stay parallel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/slicing/slice.h"
#include "support/meshes.h"

namespace polyaxis::slicing {
namespace {

constexpr double kPi = 3.14159265358979323846;

mesh::Mesh repaired(io::RawMesh raw) {
  auto r = mesh::repair(std::move(raw));
  EXPECT_TRUE(r.ok());
  return r.value().mesh;
}

SliceOptions tilted_options(double min_mm = 0.3, double max_mm = 0.7) {
  SliceOptions o;
  o.tilted = true;
  o.layer_mm = 0.6;
  o.min_mm = min_mm;
  o.max_mm = max_mm;
  o.limits.voldiff = 0.05;
  o.limits.overhang_deg = 30.0;
  o.limits.overhang_step_mm = 0.45;
  return o;
}

double angle_deg(core::Vec3 a, core::Vec3 b) {
  return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)) * 180.0 / kPi;
}

// The polygons of layer A in layer B's (u, v) frame, projected along B's normal.
std::vector<geom2d::Polygon> projected(const Layer& a, const Layer& b) {
  std::vector<geom2d::Ring> rings;
  for (const geom2d::Ring& r : geom2d::rings_of(a.polygons)) {
    geom2d::Ring out;
    for (const geom2d::Point& q : r) {
      const core::Vec3 w = a.frame.to_world(geom2d::to_mm(q.x), geom2d::to_mm(q.y)) - b.frame.origin;
      out.push_back({geom2d::to_units(core::dot(w, b.frame.u)), geom2d::to_units(core::dot(w, b.frame.v))});
    }
    rings.push_back(out);
  }
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

struct Figures {
  double least = INFINITY, most = 0.0;  // thickness over every corner of every layer after the first
  double largest_turn_deg = 0.0;        // between consecutive planes
  double overhang_mm2 = 0.0;            // beyond the layer below grown by the limit
};

// Measures SLICES independently of the slicer's own records.
Figures measure(const SliceResult& slices, const SliceOptions& o) {
  Figures f;
  const auto& ls = slices.layers;
  for (std::size_t k = 1; k < ls.size(); ++k) {
    const Layer &a = ls[k - 1], &b = ls[k];
    const core::Vec3 n = a.frame.d, d = b.frame.d;
    f.largest_turn_deg = std::max(f.largest_turn_deg, angle_deg(n, d));
    double t_min = INFINITY;
    for (const geom2d::Ring& r : geom2d::rings_of(b.polygons)) {
      for (const geom2d::Point& q : r) {
        const core::Vec3 p = b.frame.to_world(geom2d::to_mm(q.x), geom2d::to_mm(q.y));
        const double t = core::dot(p - a.frame.origin, n) / core::dot(d, n);  // along d down to a's plane
        f.least = std::min(f.least, t), f.most = std::max(f.most, t), t_min = std::min(t_min, t);
      }
    }
    const double grow = std::max(t_min * std::tan(*o.limits.overhang_deg * kPi / 180.0), *o.limits.overhang_step_mm);
    const auto beyond = geom2d::difference_rings(geom2d::rings_of(b.polygons), geom2d::rings_of(geom2d::offset(projected(a, b), grow)));
    f.overhang_mm2 += geom2d::area_mm2(beyond);
  }
  return f;
}

struct Bend {
  double r_bend, r_bar, sweep_deg;
  std::uint32_t n, m;
};

class TiltedOnBentBars : public ::testing::TestWithParam<Bend> {};

TEST_P(TiltedOnBentBars, PlanesFollowTheBarWithThicknessInRange) {
  const Bend b = GetParam();
  const mesh::Mesh bar = repaired(test::bent_bar(b.r_bend, b.r_bar, b.sweep_deg, b.n, b.m));
  const SliceOptions o = tilted_options();
  auto r = slice(bar, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const SliceResult& s = r.value();
  ASSERT_GT(s.layers.size(), 10u);
  EXPECT_EQ(s.open_chains, 0u);
  // Only where the bar ends: the flat cap leaves a last sliver no turn can follow.
  EXPECT_LE(s.limit_violations, 2u);
  const Figures f = measure(s, o);
  EXPECT_GE(f.least, o.min_mm - 1e-4);
  EXPECT_LE(f.most, o.max_mm + 1e-4);
  EXPECT_LT(f.overhang_mm2, 0.01);
  EXPECT_GT(f.largest_turn_deg, 0.2);  // consecutive planes are not parallel
  // The last plane is square to the bar's far end, which leans SWEEP from +Z.
  EXPECT_NEAR(angle_deg(s.layers.back().frame.d, {0, 0, 1}), b.sweep_deg, 10.0);
  for (const Layer& l : s.layers) {
    for (const auto& p : l.polygons) EXPECT_TRUE(geom2d::is_simple(p.outer)) << "layer " << l.index;
    const auto [lo, hi] = l.thickness_range();
    EXPECT_LE(lo, hi);
  }
  // Σ area × thickness on the axis against the bar's volume.
  const double volume = mesh::signed_volume(bar);
  EXPECT_NEAR(s.volume_estimate_mm3, volume, 0.05 * volume);
}

// A straight bar leaning nowhere: the planes stay parallel, as planar slicing's would.
TEST(Tilted, StraightBarKeepsParallelPlanes) {
  const mesh::Mesh bar = repaired(test::frustum(8, 8, 30, 40));
  const SliceOptions o = tilted_options();
  auto r = slice(bar, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Figures f = measure(r.value(), o);
  EXPECT_LT(f.largest_turn_deg, 1e-6);
  EXPECT_NEAR(f.least, 0.6, 1e-6);
  EXPECT_NEAR(f.most, 0.6, 1e-6);
  EXPECT_EQ(r.value().limit_violations, 0u);
  EXPECT_EQ(r.value().layers.size(), 50u);  // 30 mm at 0.6
}

// The planes are the same whatever the bar's place and turn in space.
TEST(Tilted, FollowsTheBarInAnyFrame) {
  io::RawMesh raw = test::bent_bar(40, 8, 90, 48, 16);
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (auto& p : raw.points) {
    const double x = p.x, y = p.y;
    p.x = c * x - s * y + 13.0, p.y = s * x + c * y - 4.0, p.z += 2.5;
  }
  const mesh::Mesh bar = repaired(raw);
  SliceOptions o = tilted_options();
  auto r = slice(bar, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Figures f = measure(r.value(), o);
  EXPECT_GE(f.least, o.min_mm - 1e-4);
  EXPECT_LE(f.most, o.max_mm + 1e-4);
  EXPECT_LT(f.overhang_mm2, 0.01);
  // The far end leans 90° from +Z towards the turned +X.
  EXPECT_NEAR(angle_deg(r.value().layers.back().frame.d, {c, s, 0}), 0.0, 10.0);
}

// The spiral (a thin square tube on a helix, leaning 70° from its horizontal base): planes turning at
// most as fast as the thickness range allows fall behind the helix and wander off it. The slicing
// is refused, naming how much of the part the layers would cover, rather than returned short.
// The reference spiral (a hollow square tube on a helix of radius 18, leaning 70° from the
// vertical), and solid bars on other helices: the planes turn from the flat first layer towards
// the bar and then follow the helix to its end. The nominal step (0.6 mm, near the top of the
// range) leaves the planes little room to turn; the middle of the range leaves them the most.
TEST(Tilted, PlanesFollowAHelixToItsEnd) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/spiral.stl");
  ASSERT_TRUE(read.ok());
  struct Case {
    std::string name;
    mesh::Mesh m;
  };
  std::vector<Case> cases;
  cases.push_back({"spiral", repaired(std::move(read.value().mesh))});
  cases.push_back({"bar w8 r15 1.25 turns", repaired(test::helical_bar(8, 15, 1.25, 50, 0.5))});
  cases.push_back({"bar w6 r24 1 turn", repaired(test::helical_bar(6, 24, 1.0, 70, 0.5))});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const SliceOptions o = tilted_options();
    auto r = slice(c.m, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const double volume = std::fabs(mesh::signed_volume(c.m));
    EXPECT_GT(r.value().volume_estimate_mm3, 0.97 * volume);
    EXPECT_LT(r.value().volume_estimate_mm3, 1.15 * volume);
    double most = 0.0;
    for (const Layer& l : r.value().layers) {
      EXPECT_GE(l.thickness_range().first, o.min_mm - 1e-6) << l.index;
      EXPECT_LE(l.thickness_range().second, o.max_mm + 1e-6) << l.index;
      most = std::max(most, std::acos(std::clamp(l.frame.d.z, -1.0, 1.0)) * 180.0 / 3.14159265358979323846);
    }
    EXPECT_GT(most, 55.0);  // the planes lean with the bar
  }
}

// A bar 18 mm wide on the spiral's helix turns faster than the planes can (their turn per layer is
// bounded by the thickness range over the section's width): they fall behind and lose it, and the
// slicing is refused.
TEST(Tilted, PlanesThatCannotTurnWithThePartAreRefused) {
  const mesh::Mesh tight = repaired(test::helical_bar(18, 18, 1.5, 60, 0.5));
  auto r = slice(tight, tilted_options());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
  EXPECT_NE(r.error().message.find("% of the part's volume"), std::string::npos) << r.error().message;
}

// A flared cup overhangs all round: no plane turned one way helps. With a budget of overhang the
// slicing stops as soon as the layers that give up the overhang limit exceed it.
TEST(Tilted, GivesUpOnceTheOverhangBudgetIsSpent) {
  const mesh::Mesh cup = repaired(test::frustum(5, 30, 20, 64));  // its side leans 51° out
  SliceOptions o = tilted_options();
  auto all = slice(cup, o);
  ASSERT_TRUE(all.ok()) << all.error().message;
  EXPECT_GT(all.value().limit_violations, 10u);
  o.give_up_overhang_mm2 = 5.0;
  auto stopped = slice(cup, o);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.error().code, core::ErrorCode::kInfeasible);
  EXPECT_NE(stopped.error().message.find("more than 5.0 mm2 of overhang"), std::string::npos) << stopped.error().message;
  o.give_up_overhang_mm2 = 1e9;
  EXPECT_TRUE(slice(cup, o).ok());
}

// A plate thinner than the nominal step is one layer of its own thickness, not a 0.6 mm layer over
// a 0.4 mm plate (found planning a thin plate: half as much again deposited).
TEST(Tilted, APlateThinnerThanAStepIsOneLayerOfItsThickness) {
  const mesh::Mesh plate = repaired(test::box({0, 0, 0}, {80, 80, 0.4}));
  auto r = slice(plate, tilted_options());
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r.value().layers.size(), 1u);
  EXPECT_NEAR(r.value().layers[0].thickness_mm(), 0.4, 1e-9);
  EXPECT_NEAR(r.value().volume_estimate_mm3, 80.0 * 80.0 * 0.4, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Bends, TiltedOnBentBars,
                         ::testing::Values(Bend{40, 8, 110, 48, 16}, Bend{60, 6, 60, 30, 24}, Bend{30, 5, 90, 64, 12},
                                           Bend{50, 10, 135, 40, 32}));

}  // namespace
}  // namespace polyaxis::slicing
