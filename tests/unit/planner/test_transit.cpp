// The transit between regions: out along the old axis, over a sphere around the part with the
// nozzle pointing away from it, in along the new axis; small steps; never over the part.
#include <gtest/gtest.h>

#include <cmath>

#include "planner/transit.h"

namespace polyaxis::planner {
namespace {

constexpr double kPi = 3.14159265358979323846;

double angle_deg(Vec3 a, Vec3 b) {
  return std::atan2(core::norm(core::cross(a, b)), core::dot(a, b)) * 180.0 / kPi;
}

// Does the ray P + s·D (s >= 0) come within R0 of C?
bool ray_enters_ball(Vec3 p, Vec3 d, Vec3 c, double r0) {
  const Vec3 q = p - c;
  const double s = std::max(0.0, -core::dot(q, d));
  return core::norm(q + d * s) < r0;
}

void check_transit(Vec3 from, Vec3 a, Vec3 to, Vec3 b) {
  const Vec3 centre{1, 2, 3};
  const double part_radius = 40.0, radius = 50.0;
  const auto points = transit(from, a, to, b, centre, radius);
  ASSERT_GE(points.size(), 2u);
  // The first point is on the ray from FROM along A, the last on the ray from TO along B.
  EXPECT_LT(angle_deg(points.front().tip - from, a), 1e-6);
  EXPECT_LT(angle_deg(points.back().tip - to, b), 1e-6);
  EXPECT_LT(angle_deg(points.front().axis, a), 1e-9);
  EXPECT_LT(angle_deg(points.back().axis, b), 1e-9);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const TransitPoint& t = points[i];
    EXPECT_NEAR(core::norm(t.tip - centre), radius, 1e-9) << i;  // on the sphere
    EXPECT_NEAR(core::norm(t.axis), 1.0, 1e-12);
    EXPECT_FALSE(ray_enters_ball(t.tip, t.axis, centre, part_radius)) << i;  // the nozzle points away from the part
    if (i > 0) {
      EXPECT_LE(angle_deg(points[i - 1].axis, t.axis), kTransitStepDeg + 1e-9) << i;
      EXPECT_LE(angle_deg(points[i - 1].tip - centre, t.tip - centre), kTransitStepDeg + 1e-9) << i;
      // The chord between neighbours stays outside the part's ball.
      const Vec3 mid = (points[i - 1].tip + t.tip) * 0.5;
      EXPECT_GT(core::norm(mid - centre), part_radius) << i;
    }
  }
}

TEST(Transit, TurnsAQuarterOverThePart) {
  check_transit({1, 2, 30}, {0, 0, 1}, {30, 2, 10}, {1, 0, 0});
}

TEST(Transit, ReversesThroughAPerpendicularPole) {
  const Vec3 c{1, 2, 3};
  check_transit(c + Vec3{5, 0, 20}, {0, 0, 1}, c + Vec3{-5, 3, -20}, {0, 0, -1});
  const auto points = transit(c + Vec3{5, 0, 20}, {0, 0, 1}, c + Vec3{-5, 3, -20}, {0, 0, -1}, c, 50.0);
  double most_horizontal = 90.0;
  for (const TransitPoint& t : points) most_horizontal = std::min(most_horizontal, std::fabs(90.0 - angle_deg(t.axis, {0, 0, 1})));
  EXPECT_LT(most_horizontal, 1e-6);  // through a horizontal axis
}

TEST(Transit, ObliqueDirectionsAndOffCentreEnds) {
  check_transit({10, -5, 0}, {0.6, 0, 0.8}, {-20, 10, 15}, {-0.36, 0.48, 0.8});
  check_transit({0, 0, -10}, {0, 0.6, -0.8}, {0, 0, -10}, {0, 0.6, -0.8});  // same axis: out and back
}

// Two axes 16° below the horizon, 135° and 170° apart in azimuth (the blades of an impeller on
// its hub, built one after another out of turn): the great circle between them would bow down to
// 37° and 70° below it, under the plate; the transit keeps between the two latitudes.
TEST(Transit, AxesBelowTheHorizonKeepTheirLatitudeBetweenThem) {
  const double lat = -16.0 * kPi / 180.0;
  for (const double apart_deg : {135.0, 170.0, 45.0}) {
    SCOPED_TRACE(apart_deg);
    const double half = 0.5 * apart_deg * kPi / 180.0;
    const Vec3 a{std::cos(lat) * std::cos(-half), std::cos(lat) * std::sin(-half), std::sin(lat)};
    const Vec3 b{std::cos(lat) * std::cos(half), std::cos(lat) * std::sin(half), std::sin(lat)};
    const Vec3 c{1, 2, 3};
    check_transit(c + a * 20.0, a, c + b * 20.0, b);
    const auto points = transit(c + a * 20.0, a, c + b * 20.0, b, c, 50.0);
    double lowest = 1.0;
    for (const TransitPoint& t : points) lowest = std::min(lowest, core::normalized(t.tip - c).z);
    EXPECT_GE(lowest, std::sin(lat) - 1e-9);
    // The great circle's middle, which the transit no longer takes, is lower (but for 45°, which
    // dips by under a degree and is taken as it was).
    const Vec3 mid = core::normalized(a + b);
    if (apart_deg > 90.0) {
      EXPECT_LT(mid.z, std::sin(lat) - 0.2);
    }
  }
  // Above the horizon the great circle bows upwards and is kept.
  const Vec3 a = core::normalized(Vec3{1, 0, 0.5}), b = core::normalized(Vec3{-1, 0.1, 0.5});
  const auto points = transit(a * 20.0, a, b * 20.0, b, {0, 0, 0}, 50.0);
  double highest = -1.0;
  for (const TransitPoint& t : points) highest = std::max(highest, t.axis.z);
  EXPECT_GT(highest, 0.99);
}

}  // namespace
}  // namespace polyaxis::planner
