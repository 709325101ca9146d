// The torch's tool-axis field along a contour (toolpath::smooth_tool_axes): chatter between facets
// held, tilts never lowered, the turn per mm bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::toolpath {
namespace {

constexpr double kPi = 3.14159265358979323846;
const Vec3 kUp{0, 0, 1};

double tilt_deg(Vec3 a) { return std::atan2(core::norm(core::cross(a, kUp)), core::dot(a, kUp)) * 180.0 / kPi; }
Vec3 leaning(double deg, Vec3 side) { return core::normalized(kUp * std::cos(deg * kPi / 180.0) + side * std::sin(deg * kPi / 180.0)); }

TEST(AxisField, ChatterBetweenFacetsBecomesOneHeldTilt) {
  // A circle of radius 20 mm, points 0.3 mm apart; Kapil's axes alternate 0°, 31°, 0°, 33° on a
  // 60° stretch of it (the facets of a tessellated overhang), leaning outwards.
  const int n = 419;
  std::vector<Vec3> pts, axes;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    pts.push_back({20.0 * std::cos(a), 20.0 * std::sin(a), 5.0});
    const Vec3 out{std::cos(a), std::sin(a), 0.0};
    const bool overhang = a < kPi / 3.0;
    axes.push_back(overhang && i % 2 == 1 ? leaning(i % 4 == 1 ? 31.0 : 33.0, out) : kUp);
  }
  const std::vector<Vec3> raw = axes;
  smooth_tool_axes(pts, axes, kUp, true, 1.0, 3.75);
  for (int i = 0; i < n; ++i) {
    // Never less tilted than asked; unit.
    EXPECT_GE(tilt_deg(axes[i]) + 1e-9, tilt_deg(raw[i])) << i;
    EXPECT_NEAR(core::norm(axes[i]), 1.0, 1e-12);
    // The turn between neighbours is bounded by the rate (3.75°/mm × 0.3 mm), plus the lean's own
    // turn round the circle (0.86° a step).
    const Vec3 a = axes[i], b = axes[(i + 1) % n];
    const double turn = std::atan2(core::norm(core::cross(a, b)), core::dot(a, b)) * 180.0 / kPi;
    EXPECT_LE(turn, 3.75 * core::norm(pts[(i + 1) % n] - pts[i]) + 0.9 + 1e-9) << i;
  }
  // Inside the overhang no point is left upright between two tilted ones.
  for (int i = 5; i < n / 6 - 5; ++i) EXPECT_GE(tilt_deg(axes[i]), 31.0 - 1e-9) << i;
  // Far from it the torch is upright again.
  EXPECT_LT(tilt_deg(axes[n / 2]), 1e-9);
}

TEST(AxisField, UprightContoursAreLeftAlone) {
  std::vector<Vec3> pts{{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  std::vector<Vec3> axes(4, kUp);
  smooth_tool_axes(pts, axes, kUp, true, 1.0, 3.75);
  for (const Vec3& a : axes) EXPECT_EQ(a, kUp);
}

TEST(AxisField, AnOpenPathRampsDownAtTheRateFromItsTiltedEnd) {
  std::vector<Vec3> pts, axes;
  for (int i = 0; i <= 20; ++i) pts.push_back({static_cast<double>(i), 0, 0}), axes.push_back(kUp);
  axes[0] = leaning(40.0, {0, 1, 0});
  smooth_tool_axes(pts, axes, kUp, false, 0.5, 5.0);
  for (int i = 0; i <= 20; ++i) EXPECT_NEAR(tilt_deg(axes[i]), std::max(0.0, 40.0 - 5.0 * i), 1e-9) << i;
}

}  // namespace
}  // namespace polyaxis::toolpath
