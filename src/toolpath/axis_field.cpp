// The torch's tool-axis field along a contour (toolpath.h, smooth_tool_axes). Kapil's Eq. 3 gives
// each contour point the axis of its own facet, so on a tessellated surface the tilt jumps between
// 0 and the full overhang angle from one point to the next (0°, 31°, 0°, 33°); a table-table
// machine follows each jump with a rotary move while the tip hardly moves. Holding the largest
// lean over a short window and ramping it down at a bounded rate gives a field the rotary axes
// can follow at the deposit feed, without tilting less where Eq. 3 asked for a tilt.
#include <algorithm>
#include <cmath>

#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::toolpath {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Leans below this (sine of the tilt) have no direction worth keeping.
constexpr double kNoLean = 1e-9;
// The window looks at most this many points each way (contours with dense points).
constexpr std::size_t kMaxWindowPoints = 64;

}  // namespace

void smooth_tool_axes(const std::vector<Vec3>& points, std::vector<Vec3>& axes, Vec3 d, bool closed, double window_mm,
                      double turn_deg_per_mm) {
  const std::size_t n = points.size();
  if (n < 2 || axes.size() != n) return;
  d = core::normalized(d);
  std::vector<Vec3> lean(n);
  std::vector<double> tilt(n);
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = core::normalized(axes[i]);
    lean[i] = a - d * core::dot(a, d);
    tilt[i] = std::atan2(core::norm(lean[i]), core::dot(a, d));
    any = any || tilt[i] > 0.0;
  }
  if (!any) return;
  // Arc length from point i to i+1 (and from the last to the first on a closed loop).
  auto step = [&](std::size_t i) { return core::norm(points[(i + 1) % n] - points[i]); };
  // 1. Largest tilt within the window, in the summed lean direction there.
  std::vector<double> held(n);
  std::vector<Vec3> dir(n);
  for (std::size_t i = 0; i < n; ++i) {
    double best = tilt[i];
    Vec3 sum = lean[i];
    for (int side = -1; side <= 1; side += 2) {
      double walked = 0.0;
      std::size_t j = i;
      for (std::size_t k = 1; k < std::min(n, kMaxWindowPoints + 1); ++k) {
        if (side > 0) {
          if (!closed && j + 1 >= n) break;
          walked += step(j);
          j = (j + 1) % n;
        } else {
          if (!closed && j == 0) break;
          j = (j + n - 1) % n;
          walked += step(j);
        }
        if (walked > window_mm) break;
        best = std::max(best, tilt[j]);
        sum = sum + lean[j];
      }
    }
    held[i] = best;
    dir[i] = core::norm(sum) > kNoLean ? core::normalized(sum) : Vec3{};
  }
  // 2. Ramp down at the bounded rate, both ways (two laps round a closed loop reach every point).
  const double rate = turn_deg_per_mm * kPi / 180.0;
  const std::size_t laps = closed ? 2 : 1;
  for (std::size_t pass = 0; pass < laps * n; ++pass) {
    const std::size_t i = (pass + 1) % n, prev = pass % n;
    if (!closed && i == 0) continue;
    const double from_prev = held[prev] - rate * step(prev);
    if (from_prev > held[i]) {
      held[i] = from_prev;
      if (core::norm(dir[i]) == 0.0) dir[i] = dir[prev];
    }
  }
  for (std::size_t pass = 0; pass < laps * n; ++pass) {
    const std::size_t i = (2 * laps * n - 1 - pass) % n, next = (i + 1) % n;
    if (!closed && i + 1 >= n) continue;
    const double from_next = held[next] - rate * step(i);
    if (from_next > held[i]) {
      held[i] = from_next;
      if (core::norm(dir[i]) == 0.0) dir[i] = dir[next];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (held[i] <= 0.0 || core::norm(dir[i]) == 0.0) {
      axes[i] = d;
      continue;
    }
    const double t = std::min(held[i], kMaxTiltRad);
    axes[i] = core::normalized(d * std::cos(t) + dir[i] * std::sin(t));
  }
}

}  // namespace polyaxis::toolpath
