#include "build_time.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gcode_walk.h"

namespace polyaxis::verify::detail {
namespace {

constexpr double kEps = 1e-12;
// tp.c: a corner within 2° of a reversal is an exact stop; below TP_MIN_ARC_ANGLE the tolerance
// does not bound a parabolic blend.
constexpr double kSharpCornerRad = 2.0 * 3.14159265358979323846 / 180.0;
constexpr double kMinArcAngleRad = 1e-3;
// blendmath.h: an arc blend keeps this share of the acceleration for the normal direction.
const double kBlendAccRatioNormal = std::sqrt(1.0 - 0.5 * 0.5);

double trapezoid_s(double length, double v0, double v1, double vmax, double a) {
  if (length <= 0.0) return 0.0;
  const double peak_sq = (2.0 * a * length + v0 * v0 + v1 * v1) / 2.0;
  const double peak = std::sqrt(std::max(peak_sq, 0.0));
  if (peak <= vmax) return std::max(0.0, (peak - v0) / a) + std::max(0.0, (peak - v1) / a);
  const double ramp_up = (vmax * vmax - v0 * v0) / (2.0 * a), ramp_down = (vmax * vmax - v1 * v1) / (2.0 * a);
  return (vmax - v0) / a + (vmax - v1) / a + (length - ramp_up - ramp_down) / vmax;
}

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

TimedBlock timed_block(const WalkMove& mv) {
  TimedBlock b;
  const double dx = mv.to.x_mm - mv.from.x_mm, dy = mv.to.y_mm - mv.from.y_mm, dz = mv.to.z_mm - mv.from.z_mm;
  const double l_xyz = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (mv.robot_joint || mv.arm_to) {
    b.d[0] = mv.l_xyz_mm;
    b.u_xyz[0] = 1.0;
  } else {
    b.d[0] = std::fabs(dx), b.d[1] = std::fabs(dy), b.d[2] = std::fabs(dz);
    b.d[3] = std::fabs(mv.to.a_or_b_deg - mv.from.a_or_b_deg), b.d[4] = std::fabs(mv.to.c_deg - mv.from.c_deg);
    if (l_xyz > 0.0) b.u_xyz[0] = dx / l_xyz, b.u_xyz[1] = dy / l_xyz, b.u_xyz[2] = dz / l_xyz;
  }
  b.rapid = mv.rapid;
  b.feed_per_min = mv.feed;
  // Tool-space blocks (TRAORI, G43.4) and G93 give the block's time; the joints follow it.
  if (mv.inverse_time || mv.tool_space || mv.rotary_linear || mv.robot_joint || mv.arm_to) b.inverse_time_min = mv.time_min;
  b.part = mv.process_on ? BuildTimePart::kDeposit : (l_xyz > 0.0 || mv.l_xyz_mm > 0.0) ? BuildTimePart::kTravel : BuildTimePart::kReorientation;
  return b;
}

BuildTimer::BuildTimer(const machine::MachineConfig& machine, bool keep_durations) : m_(machine), keep_durations_(keep_durations) {}

void BuildTimer::move(const WalkMove& mv) {
  if (mv.process_on != last_on_) dwell(0.0);
  last_on_ = mv.process_on;
  block(timed_block(mv));
}

void BuildTimer::block(const TimedBlock& b) {
  const std::size_t slot = durations_.size();
  if (keep_durations_) durations_.push_back(0.0);
  const double l_xyz = std::sqrt(b.d[0] * b.d[0] + b.d[1] * b.d[1] + b.d[2] * b.d[2]);
  const double l_rot = std::hypot(b.d[3], b.d[4]);
  if (l_xyz < kEps && l_rot < kEps) return;
  Segment s;
  s.slot = slot;
  s.length = l_xyz >= kEps ? l_xyz : l_rot;
  s.rotary = l_rot >= kEps;
  std::copy(b.u_xyz, b.u_xyz + 3, s.u);
  s.part = b.part;
  const double v_lin = m_.feed.linear_max_mm_min / 60.0, v_rot = m_.feed.rotary_max_deg_min / 60.0;
  const double limits_v[5] = {v_lin, v_lin, v_lin, v_rot, v_rot};
  const double limits_a[5] = {m_.accel.linear_mm_s2, m_.accel.linear_mm_s2, m_.accel.linear_mm_s2, m_.accel.rotary_deg_s2,
                              m_.accel.rotary_deg_s2};
  double vmax = std::numeric_limits<double>::infinity(), accel = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 5; ++i) {
    if (b.d[i] < kEps) continue;
    vmax = std::min(vmax, limits_v[i] * s.length / b.d[i]);
    accel = std::min(accel, limits_a[i] * s.length / b.d[i]);
  }
  if (!b.rapid) {
    const double requested = b.inverse_time_min > 0.0 ? s.length / (b.inverse_time_min * 60.0) : b.feed_per_min / 60.0;
    vmax = std::min(vmax, requested);
  }
  s.vmax = std::min(vmax, s.length / kServoPeriodS);  // tcClampVelocityByLength
  s.accel = accel;
  chain_.push_back(s);
}

void BuildTimer::dwell(double seconds) {
  flush();
  time_.dwell_s += std::max(seconds, 0.0);
}

BuildTime BuildTimer::finish() {
  flush();
  time_.total_s = time_.deposit_s + time_.travel_s + time_.reorientation_s + time_.dwell_s;
  return time_;
}

void BuildTimer::flush() {
  const std::size_t n = chain_.size();
  // (The bound tells GCC's allocation-size check that n + 1 cannot wrap.)
  if (n == 0 || n > std::size_t{1} << 40) return;
  enum class Join { kStop, kParabolic, kContinuous };
  std::vector<Join> join(n, Join::kStop);     // join[k]: between k and k + 1 (the last: the chain's end)
  std::vector<double> v_join(n + 1, 0.0);     // velocity at each join (continuous ones only)
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const Segment& a = chain_[k];
    const Segment& b = chain_[k + 1];
    if (a.rotary || b.rotary) {
      join[k] = Join::kParabolic;
      continue;
    }
    const double dot = std::clamp(dot3(a.u, b.u), -1.0, 1.0);
    if (dot < -std::cos(kSharpCornerRad)) continue;  // a reversal: exact stop
    join[k] = Join::kContinuous;
    const double half = std::acos(-dot) / 2.0;  // half the corner's inner angle (findIntersectionAngle)
    double v = std::min(a.vmax, b.vmax);
    if (std::sin(half) < 1.0 - 1e-9) {
      // A circular blend within the tolerance, consuming at most half of either block.
      const double s = std::sin(half);
      double radius = m_.accel.blend_tolerance_mm * s / (1.0 - s);
      radius = std::min(radius, 0.5 * std::min(a.length, b.length) * std::tan(half));
      v = std::min(v, std::sqrt(kBlendAccRatioNormal * std::min(a.accel, b.accel) * std::max(radius, 0.0)));
    }
    v_join[k + 1] = v;
  }
  // Parabolic blends halve the acceleration of both blocks (tc.c, tcGetOverallMaxAccel).
  std::vector<double> acc(n);
  for (std::size_t k = 0; k < n; ++k) {
    const bool blended = (k > 0 && join[k - 1] == Join::kParabolic) || join[k] == Join::kParabolic;
    acc[k] = chain_[k].accel * (blended ? 0.5 : 1.0);
  }
  // Velocities at continuous joins, reachable from both sides (backward, then forward).
  for (std::size_t k = n; k-- > 0;) {
    const double end = k + 1 < n && join[k] == Join::kContinuous ? v_join[k + 1] : 0.0;
    if (k > 0 && join[k - 1] == Join::kContinuous) {
      v_join[k] = std::min(v_join[k], std::sqrt(end * end + 2.0 * acc[k] * chain_[k].length));
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double start = k > 0 && join[k - 1] == Join::kContinuous ? v_join[k] : 0.0;
    if (k + 1 < n && join[k] == Join::kContinuous) {
      v_join[k + 1] = std::min(v_join[k + 1], std::sqrt(start * start + 2.0 * acc[k] * chain_[k].length));
    }
  }
  auto part_time = [&](BuildTimePart p) -> double& {
    return p == BuildTimePart::kDeposit ? time_.deposit_s : p == BuildTimePart::kReorientation ? time_.reorientation_s : time_.travel_s;
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Segment& s = chain_[k];
    const double v0 = k > 0 && join[k - 1] == Join::kContinuous ? v_join[k] : 0.0;
    const double v1 = k + 1 < n && join[k] == Join::kContinuous ? v_join[k + 1] : 0.0;
    double t = std::max(trapezoid_s(s.length, v0, v1, s.vmax, acc[k]), kServoPeriodS);
    if (k + 1 < n && join[k] == Join::kParabolic) {
      // The next block starts while this one slows below the blend velocity (tpComputeBlendVelocity):
      // that part of the slowing overlaps the next block's start.
      const Segment& b = chain_[k + 1];
      const double reach_this = std::min(s.vmax, std::sqrt(acc[k] * s.length));
      const double reach_next = std::min(b.vmax, std::sqrt(acc[k + 1] * b.length / 2.0));
      const double t_reachable = std::min(s.length / reach_this, b.length / reach_next);
      const double t_blend = std::min(t_reachable, std::max(reach_this / acc[k], reach_next / acc[k + 1]));
      double v_blend = std::min(reach_this, t_blend * acc[k]);
      const double cos_half = std::cos(std::acos(std::clamp(-dot3(s.u, b.u), -1.0, 1.0)) / 2.0);
      if (cos_half > std::cos(3.14159265358979323846 / 2.0 - kMinArcAngleRad)) {
        v_blend = std::min(v_blend, 2.0 * std::sqrt(acc[k] * m_.accel.blend_tolerance_mm / cos_half));
      }
      t -= std::min(v_blend / acc[k], t - kServoPeriodS);
    }
    part_time(s.part) += t;
    if (keep_durations_) durations_[s.slot] = t;
  }
  chain_.clear();
}

}  // namespace polyaxis::verify::detail
