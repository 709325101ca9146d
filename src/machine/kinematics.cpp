// Table-table kinematics after LinuxCNC's trtfuncs.c (xyzac-trt-kins, xyzbc-trt-kins), written as
// rotations about the pivot; see the header for the formula and the frames.
#include "polyaxis/machine/kinematics.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>

namespace polyaxis::machine {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

Vec3 rot_x(Vec3 v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {v.x, c * v.y - s * v.z, s * v.y + c * v.z};
}
Vec3 rot_y(Vec3 v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}
Vec3 rot_z(Vec3 v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

bool is_a(const MachineConfig& m) { return tilt_axis_letter(m.kind) == 'A'; }
Vec3 rot_tilt(const MachineConfig& m, Vec3 v, double a) { return is_a(m) ? rot_x(v, a) : rot_y(v, a); }

// s in the header's formula: LinuxCNC 2.9 turns its tables opposite to the conventional sense.
double sense(const MachineConfig& m) { return m.pivot.conventional_directions ? 1.0 : -1.0; }

Vec3 rot_point(const MachineConfig& m) { return {m.pivot.x_rot_point_mm, m.pivot.y_rot_point_mm, m.pivot.z_rot_point_mm}; }

// d: the tilt axis relative to the C axis; trt-kins adds the tool offset to its z (dz = z_offset + dt).
Vec3 tilt_offset(const MachineConfig& m) {
  const double dz = m.pivot.z_offset_mm + m.pivot.tool_offset_mm;
  return is_a(m) ? Vec3{0.0, m.pivot.y_offset_mm, dz} : Vec3{m.pivot.x_offset_mm, 0.0, dz};
}

// The joint positions that put part point P under the tool at rotary angles (radians, already
// multiplied by s): joints = rp + d + Rt(−t)·(Rz(−c)·(P − rp) − d).
Vec3 joints_for(const MachineConfig& m, Vec3 p, double tilt_rad_s, double c_rad_s) {
  const Vec3 rp = rot_point(m), d = tilt_offset(m);
  return rp + d + rot_tilt(m, rot_z(p - rp, -c_rad_s) - d, -tilt_rad_s);
}

// Head-head machines (kinematics.h): the tool axis at tilt T and turn C (radians), and the joints
// that put the tip at TIP with it: joints = tip − L·(ẑ − axis).
Vec3 head_axis(const MachineConfig& m, double t, double c) {
  const Vec3 tilted = is_a(m) ? Vec3{0.0, -std::sin(t), std::cos(t)} : Vec3{-std::sin(t), 0.0, std::cos(t)};
  return rot_z(tilted, c);
}
Vec3 head_joints(const MachineConfig& m, Vec3 tip, double t, double c) {
  return tip - (Vec3{0.0, 0.0, 1.0} - head_axis(m, t, c)) * m.pivot.pivot_length_mm;
}

std::string fmt_num(double v) { return fmt::format("{:.4f}", v); }

std::string check_range(char axis, double v, const AxisRange& r, const char* unit) {
  if (v < r.min - kAxisLimitSlack) return fmt::format("{} = {}{} is beyond its minimum {}{}", axis, fmt_num(v), unit, r.min, unit);
  if (v > r.max + kAxisLimitSlack) return fmt::format("{} = {}{} is beyond its maximum {}{}", axis, fmt_num(v), unit, r.max, unit);
  return {};
}

}  // namespace

std::string limit_violation(const MachineConfig& m, const MachinePose& pose) {
  std::string v = check_range('X', pose.x_mm, m.x_mm, " mm");
  if (v.empty()) v = check_range('Y', pose.y_mm, m.y_mm, " mm");
  if (v.empty()) v = check_range('Z', pose.z_mm, m.z_mm, " mm");
  if (v.empty() && has_rotary_axes(m.kind)) {
    v = check_range(tilt_axis_letter(m.kind), pose.a_or_b_deg, m.tilt_deg, "°");
    if (v.empty() && !m.c_continuous) v = check_range('C', pose.c_deg, m.c_deg, "°");
  }
  return v;
}

std::string format_pose(const MachineConfig& m, const MachinePose& pose) {
  std::string s = fmt::format("X{} Y{} Z{}", fmt_num(pose.x_mm), fmt_num(pose.y_mm), fmt_num(pose.z_mm));
  if (has_rotary_axes(m.kind)) {
    s += fmt::format(" {}{} C{}", tilt_axis_letter(m.kind), fmt_num(pose.a_or_b_deg), fmt_num(pose.c_deg));
  }
  return s;
}

MachineToolPose forward(const MachineConfig& m, const MachinePose& pose) {
  const Vec3 j{pose.x_mm, pose.y_mm, pose.z_mm};
  if (!has_rotary_axes(m.kind)) return {j, {0.0, 0.0, 1.0}};
  if (tilts_head(m.kind)) {
    const double t = pose.a_or_b_deg * kRadPerDeg, c = pose.c_deg * kRadPerDeg;
    const Vec3 axis = head_axis(m, t, c);
    return {j + (Vec3{0.0, 0.0, 1.0} - axis) * m.pivot.pivot_length_mm, axis};
  }
  const double s = sense(m);
  const double t = s * pose.a_or_b_deg * kRadPerDeg, c = s * pose.c_deg * kRadPerDeg;
  const Vec3 rp = rot_point(m), d = tilt_offset(m);
  const Vec3 tip = rp + rot_z(rot_tilt(m, j - rp - d, t) + d, c);
  const Vec3 axis = rot_z(rot_tilt(m, {0.0, 0.0, 1.0}, t), c);
  return {tip, axis};
}

namespace {

bool within_range(double v, const AxisRange& r) { return v >= r.min - kAxisLimitSlack && v <= r.max + kAxisLimitSlack; }

// limit_violation(M, POSE).empty(), without making the message.
bool within_limits(const MachineConfig& m, const MachinePose& pose) {
  if (!within_range(pose.x_mm, m.x_mm) || !within_range(pose.y_mm, m.y_mm) || !within_range(pose.z_mm, m.z_mm)) return false;
  if (!has_rotary_axes(m.kind)) return true;
  return within_range(pose.a_or_b_deg, m.tilt_deg) && (m.c_continuous || within_range(pose.c_deg, m.c_deg));
}

// What inverse() solves, in numbers: the chosen branch's pose and whether it is inside the limits
// (the message is made only where it is needed). U: the unit tool axis; TILT_RAD: its angle from +Z.
struct Solution {
  MachinePose pose;
  bool inside = false;
};

Solution solve_rotary(const MachineConfig& m, Vec3 tip, Vec3 u, double tilt_rad, const MachinePose* previous) {
  const bool head = tilts_head(m.kind);
  const double s = head ? 1.0 : sense(m);
  const double prev_t = previous ? previous->a_or_b_deg : 0.0;
  const double prev_c = previous ? previous->c_deg : 0.0;

  // Rotary solutions in the math convention (tilt τ, turn φ): the axis is Rz(φ)·Rt(τ)·ẑ, which is
  // (sinφ·sinτ, −cosφ·sinτ, cosτ) about X and (cosφ·sinτ, sinφ·sinτ, cosτ) about Y on a table, and
  // the head's axis (kinematics.h) at T = τ, C = φ on a head (its B tilts the other way: −cosφ·sinτ, −sinφ·sinτ).
  std::array<std::pair<double, double>, 2> branches{};  // (τ, φ) in radians
  const bool singular = tilt_rad < kSingularTiltRad || tilt_rad > std::numbers::pi - kSingularTiltRad;
  if (singular) {
    // C is undefined: keep it, and tilt within that C's plane to come as close as possible. Near
    // a half turn (the tool upside down) τ and τ ∓ 2π are the same orientation: both are
    // candidates, so the tilt does not swing a full turn between +180° and −180°.
    const double phi = s * prev_c * kRadPerDeg;
    const Vec3 v = rot_z(u, -phi);
    const double tau = is_a(m) ? std::atan2(-v.y, v.z) : std::atan2(head ? -v.x : v.x, v.z);
    branches[0] = {tau, phi};
    branches[1] = {tau - std::copysign(2.0 * std::numbers::pi, tau), phi};
  } else {
    const double phi = is_a(m) ? std::atan2(u.x, -u.y) : head ? std::atan2(-u.y, -u.x) : std::atan2(u.y, u.x);
    branches[0] = {tilt_rad, phi};
    branches[1] = {-tilt_rad, phi + std::numbers::pi};
  }

  Solution best;
  double best_cost = 0.0;
  bool have_best = false;
  for (std::size_t b = 0; b < branches.size(); ++b) {
    const auto [tau, phi] = branches[b];
    const double t_deg = s * tau * kDegPerRad;
    double c_deg = s * phi * kDegPerRad;
    if (singular) {
      c_deg = prev_c;  // held exactly, not through a round trip of conversions
    } else {
      c_deg += 360.0 * std::round((prev_c - c_deg) / 360.0);  // unwrap next to the previous C
      if (!m.c_continuous && (c_deg < m.c_deg.min - kAxisLimitSlack || c_deg > m.c_deg.max + kAxisLimitSlack)) {
        // The nearest equivalent turn inside the end stops (RELIABILITY O6).
        double inside = c_deg;
        double best_dist = INFINITY;
        for (int k = -4; k <= 4; ++k) {
          const double cand = c_deg + 360.0 * k;
          if (cand >= m.c_deg.min - kAxisLimitSlack && cand <= m.c_deg.max + kAxisLimitSlack &&
              std::abs(cand - prev_c) < best_dist) {
            best_dist = std::abs(cand - prev_c);
            inside = cand;
          }
        }
        c_deg = inside;
      }
    }
    const Vec3 j = head ? head_joints(m, tip, t_deg * kRadPerDeg, c_deg * kRadPerDeg) : joints_for(m, tip, s * t_deg * kRadPerDeg, s * c_deg * kRadPerDeg);
    const Solution cand{{j.x, j.y, j.z, t_deg, c_deg}, false};
    const double cost = std::abs(t_deg - prev_t) + std::abs(c_deg - prev_c);
    const bool inside = within_limits(m, cand.pose);
    // Feasible beats infeasible, then least rotary motion; ties keep the first (positive τ) branch.
    const bool better = !have_best || (inside && !best.inside) || (inside == best.inside && cost < best_cost);
    if (better) {
      best = {cand.pose, inside};
      best_cost = cost;
      have_best = true;
    }
  }
  return best;
}

}  // namespace

core::Result<MachinePose> inverse(const MachineConfig& m, Vec3 tip, Vec3 axis_in, const MachinePose* previous) {
  const double len = norm(axis_in);
  if (!is_finite(tip) || !is_finite(axis_in) || !(len > 0.0)) {
    return core::make_error(core::ErrorCode::kInternal,
                            fmt::format("inverse kinematics: tip ({}, {}, {}) or tool axis ({}, {}, {}) is zero or not finite",
                                        tip.x, tip.y, tip.z, axis_in.x, axis_in.y, axis_in.z));
  }
  const Vec3 u = axis_in / len;
  const double tilt_rad = std::atan2(std::hypot(u.x, u.y), u.z);  // angle from +Z, in [0, π]

  if (!has_rotary_axes(m.kind)) {
    if (tilt_rad > kThreeAxisAxisToleranceRad) {
      return core::make_error(core::ErrorCode::kMachineLimit,
                              fmt::format("the 3-axis machine '{}' cannot tilt the tool: axis ({:.6f}, {:.6f}, {:.6f}) is "
                                          "{:.4f}° from vertical",
                                          m.name, u.x, u.y, u.z, tilt_rad * kDegPerRad));
    }
    MachinePose pose{tip.x, tip.y, tip.z, 0.0, 0.0};
    if (std::string v = limit_violation(m, pose); !v.empty()) {
      return core::make_error(core::ErrorCode::kMachineLimit, fmt::format("{} (pose {})", v, format_pose(m, pose)));
    }
    return pose;
  }
  const Solution best = solve_rotary(m, tip, u, tilt_rad, previous);
  if (!best.inside) {
    return core::make_error(core::ErrorCode::kMachineLimit,
                            fmt::format("{} (pose {}; no other solution branch is inside the limits)", limit_violation(m, best.pose),
                                        format_pose(m, best.pose)));
  }
  return best.pose;
}

bool reachable(const MachineConfig& m, Vec3 tip, Vec3 axis) {
  const double len = norm(axis);
  if (!is_finite(tip) || !is_finite(axis) || !(len > 0.0)) return false;
  const Vec3 u = axis / len;
  const double tilt_rad = std::atan2(std::hypot(u.x, u.y), u.z);
  if (!has_rotary_axes(m.kind)) return tilt_rad <= kThreeAxisAxisToleranceRad && within_limits(m, {tip.x, tip.y, tip.z, 0.0, 0.0});
  return solve_rotary(m, tip, u, tilt_rad, nullptr).inside;
}

std::optional<MachinePose> joints_for_tip(const MachineConfig& m, Vec3 tip, const MachinePose& angles) {
  MachinePose p = angles;
  p.x_mm = p.y_mm = p.z_mm = 0.0;
  const Vec3 t0 = forward(m, p).tip_part_mm;
  Vec3 col[3];
  for (int k = 0; k < 3; ++k) {
    MachinePose q = p;
    (k == 0 ? q.x_mm : k == 1 ? q.y_mm : q.z_mm) = 1.0;
    col[k] = forward(m, q).tip_part_mm - t0;
  }
  const double det = core::dot(col[0], core::cross(col[1], col[2]));
  if (!(std::abs(det) > 1e-12)) return std::nullopt;
  const Vec3 r = tip - t0;  // Cramer's rule
  p.x_mm = core::dot(r, core::cross(col[1], col[2])) / det;
  p.y_mm = core::dot(col[0], core::cross(r, col[2])) / det;
  p.z_mm = core::dot(col[0], core::cross(col[1], r)) / det;
  return p;
}

}  // namespace polyaxis::machine
