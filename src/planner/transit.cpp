#include "transit.h"

#include <algorithm>
#include <cmath>

namespace polyaxis::planner {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Below this angle (radians) two unit vectors are the same direction, above π minus it opposite.
constexpr double kSameDirectionRad = 1e-9;
// A great circle between two poles that goes lower than both by more than this (in z of the unit
// direction) dips.
constexpr double kDipTolerance = 1e-9;

double angle_between(Vec3 u, Vec3 v) { return std::atan2(core::norm(core::cross(u, v)), core::dot(u, v)); }

// Spherical interpolation between unit vectors U and V (not opposite) at fraction T.
Vec3 slerp(Vec3 u, Vec3 v, double t) {
  const double w = angle_between(u, v);
  if (w < kSameDirectionRad) return u;
  const double s = std::sin(w);
  return core::normalized(u * (std::sin((1.0 - t) * w) / s) + v * (std::sin(t * w) / s));
}

// A unit vector perpendicular to A: the one nearest to the XY plane, or +X for a vertical A.
Vec3 perpendicular(Vec3 a) {
  Vec3 p = core::cross(a, Vec3{0, 0, 1});
  if (core::norm(p) < 1e-9) return Vec3{1, 0, 0};
  p = core::cross(p, a);  // in the plane of A and Z, perpendicular to A
  return core::normalized(p);
}

// Points of the arc on the sphere from direction U to direction V (both unit, not opposite), U
// excluded, V included; AXIS(dir) gives the tool axis at each.
template <typename Axis>
void arc(Vec3 u, Vec3 v, Vec3 centre, double radius, Axis axis, std::vector<TransitPoint>& out) {
  const double w = angle_between(u, v);
  if (w > kPi - 1e-6) {  // opposite: through a perpendicular direction
    const Vec3 m = perpendicular(u);
    arc(u, m, centre, radius, axis, out);
    arc(m, v, centre, radius, axis, out);
    return;
  }
  const int steps = std::max(1, static_cast<int>(std::ceil(w / (kTransitStepDeg * kPi / 180.0))));
  if (w < kSameDirectionRad) return;
  for (int i = 1; i <= steps; ++i) {
    const Vec3 dir = slerp(u, v, static_cast<double>(i) / steps);
    out.push_back({centre + dir * radius, axis(dir)});
  }
}

// The latitude of the unit vector D: radians above the XY plane.
double latitude(Vec3 d) { return std::asin(std::clamp(d.z, -1.0, 1.0)); }

// Points from direction U to direction V (unit, U excluded, V included), each also the tool axis:
// the great circle, unless it dips below the lower of the two (two axes below the horizon at
// distant azimuths: the great circle between them bows towards −Z, under the plate); then the
// latitude and the azimuth interpolated evenly, which keeps the latitude between the ends'.
void between_poles(Vec3 u, Vec3 v, Vec3 centre, double radius, std::vector<TransitPoint>& out) {
  const std::size_t first = out.size();
  arc(u, v, centre, radius, [](Vec3 dir) { return dir; }, out);
  const double floor = std::min(u.z, v.z) - kDipTolerance;
  const bool dips = std::any_of(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                                [&](const TransitPoint& t) { return t.axis.z < floor; });
  const double lu = latitude(u), lv = latitude(v);
  if (!dips || std::max(std::fabs(lu), std::fabs(lv)) > kPi / 2.0 - 1e-6) return;  // no azimuth at a pole
  out.resize(first);
  const double au = std::atan2(u.y, u.x);
  double dp = std::atan2(v.y, v.x) - au;
  while (dp > kPi) dp -= 2.0 * kPi;
  while (dp < -kPi) dp += 2.0 * kPi;
  // A step turns by at most |Δlatitude| + |Δazimuth| over the steps.
  const int steps = std::max(1, static_cast<int>(std::ceil((std::fabs(lv - lu) + std::fabs(dp)) / (kTransitStepDeg * kPi / 180.0))));
  for (int i = 1; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps, lat = lu + (lv - lu) * t, az = au + dp * t;
    const Vec3 dir = i == steps ? v : Vec3{std::cos(lat) * std::cos(az), std::cos(lat) * std::sin(az), std::sin(lat)};
    out.push_back({centre + dir * radius, dir});
  }
}

}  // namespace

Vec3 ray_exit(Vec3 p, Vec3 d, Vec3 centre, double radius) {
  const Vec3 q = p - centre;
  const double b = core::dot(q, d), c = core::dot(q, q) - radius * radius;
  if (c >= 0.0) return p;
  return p + d * (-b + std::sqrt(b * b - c));
}

std::vector<TransitPoint> transit(Vec3 from, Vec3 a, Vec3 to, Vec3 b, Vec3 centre, double radius) {
  a = core::normalized(a), b = core::normalized(b);
  std::vector<TransitPoint> out;
  const Vec3 qa = ray_exit(from, a, centre, radius), qb = ray_exit(to, b, centre, radius);
  out.push_back({qa, a});
  const Vec3 ua = core::normalized(qa - centre), ub = core::normalized(qb - centre);
  arc(ua, a, centre, radius, [&](Vec3) { return a; }, out);
  between_poles(a, b, centre, radius, out);
  arc(b, ub, centre, radius, [&](Vec3) { return b; }, out);
  if (core::norm(qb - out.back().tip) > 0.0) out.push_back({qb, b});
  return out;
}

}  // namespace polyaxis::planner
