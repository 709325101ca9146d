// The ortho-parallel robot's forward and inverse kinematics (Brandstötter et al. 2014) and the
// frames between the robot, the positioner and the part; see robot.h.
#include "polyaxis/machine/robot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace polyaxis::machine {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;
// A solution whose acos argument is beyond ±1 by less than this is taken at ±1 (the arm stretched
// straight): absorbs round-off at the edge of the reach.
constexpr double kReachSlack = 1e-12;

struct Mat3 {
  Vec3 c0{1, 0, 0}, c1{0, 1, 0}, c2{0, 0, 1};  // columns
  double at(int r, int c) const { return (c == 0 ? c0 : c == 1 ? c1 : c2)[r]; }
  Vec3 operator*(Vec3 v) const { return c0 * v.x + c1 * v.y + c2 * v.z; }
  Mat3 operator*(const Mat3& o) const { return {*this * o.c0, *this * o.c1, *this * o.c2}; }
  Mat3 transposed() const { return {{c0.x, c1.x, c2.x}, {c0.y, c1.y, c2.y}, {c0.z, c1.z, c2.z}}; }
};

Mat3 rz(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {{c, s, 0}, {-s, c, 0}, {0, 0, 1}};
}
Mat3 ry(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {{c, 0, -s}, {0, 1, 0}, {s, 0, c}};
}

Mat3 rotation(const Frame3& f) { return {f.x, f.y, f.z}; }
Frame3 frame(Vec3 origin, const Mat3& r) { return {origin, r.c0, r.c1, r.c2}; }
Frame3 compose(const Frame3& a, const Frame3& b) {  // b given in a
  const Mat3 ra = rotation(a);
  return frame(a.origin + ra * b.origin, ra * rotation(b));
}
Frame3 inverted(const Frame3& f) {
  const Mat3 rt = rotation(f).transposed();
  return frame(rt * (f.origin * -1.0), rt);
}
Frame3 floor_frame(const FloorFrame& f) {
  return frame({f.origin_mm[0], f.origin_mm[1], f.origin_mm[2]}, rz(f.rz_deg * kRadPerDeg));
}
Frame3 tool_frame(const RobotCell& r) {
  return frame_of({r.tcp_mm[0], r.tcp_mm[1], r.tcp_mm[2]}, {r.tcp_quaternion[0], r.tcp_quaternion[1], r.tcp_quaternion[2], r.tcp_quaternion[3]});
}

double model_rad(const RobotCell& r, int i, double q_deg) { return (r.sign[i] * q_deg + r.zero_deg[i]) * kRadPerDeg; }
double joint_deg(const RobotCell& r, int i, double theta_rad) { return (theta_rad * kDegPerRad - r.zero_deg[i]) / r.sign[i]; }

// The flange in the robot's base frame for model angles TH (radians).
Frame3 flange_in_base(const RobotCell& r, const std::array<double, 6>& th) {
  const double k = std::hypot(r.a2_mm, r.c3_mm), psi = std::atan2(r.a2_mm, r.c3_mm);
  const double cx1 = r.c2_mm * std::sin(th[1]) + k * std::sin(th[1] + th[2] + psi) + r.a1_mm;
  const double cz1 = r.c2_mm * std::cos(th[1]) + k * std::cos(th[1] + th[2] + psi);
  const Vec3 c = rz(th[0]) * Vec3{cx1, r.b_mm, 0.0} + Vec3{0.0, 0.0, r.c1_mm + cz1};
  const Mat3 rot = rz(th[0]) * ry(th[1] + th[2]) * rz(th[3]) * ry(th[4]) * rz(th[5]);
  return frame(c + rot.c2 * r.c4_mm, rot);
}

// The model-angle solutions (radians) for flange F in the base frame: up to 8, the arm's four
// (shoulder, elbow) branches each with both wrist flips; none for a branch out of reach.
std::vector<std::array<double, 6>> model_solutions(const RobotCell& r, const Frame3& f) {
  const Mat3 R = rotation(f);
  const Vec3 c = f.origin - R.c2 * r.c4_mm;
  std::vector<std::array<double, 6>> out;
  const double radial2 = c.x * c.x + c.y * c.y - r.b_mm * r.b_mm;
  if (radial2 < 0.0) return out;
  const double nx1 = std::sqrt(radial2) - r.a1_mm;
  const double t1 = std::atan2(c.y, c.x), t2 = std::atan2(r.b_mm, nx1 + r.a1_mm);
  const double dz = c.z - r.c1_mm;
  const double kappa2 = r.a2_mm * r.a2_mm + r.c3_mm * r.c3_mm, c22 = r.c2_mm * r.c2_mm;
  const double psi = std::atan2(r.a2_mm, r.c3_mm);
  auto safe_acos = [](double v, bool& ok) {
    if (std::abs(v) > 1.0 + kReachSlack || !std::isfinite(v)) ok = false;
    return std::acos(std::clamp(v, -1.0, 1.0));
  };
  struct Arm {
    double th1, th2, th3;
  };
  std::vector<Arm> arms;
  // Facing the wrist centre (θ1 = t1 − t2) and reaching over the back (θ1 + π).
  for (const bool back : {false, true}) {
    const double n = back ? nx1 + 2.0 * r.a1_mm : nx1;
    const double s2 = n * n + dz * dz;
    if (!(s2 > 0.0)) continue;
    bool ok = true;
    const double a2 = safe_acos((s2 + c22 - kappa2) / (2.0 * std::sqrt(s2) * r.c2_mm), ok);
    const double a3 = safe_acos((s2 - c22 - kappa2) / (2.0 * r.c2_mm * std::sqrt(kappa2)), ok);
    if (!ok) continue;
    const double th1 = back ? t1 + t2 - std::numbers::pi : t1 - t2;
    const double base2 = back ? -std::atan2(n, dz) : std::atan2(n, dz);
    arms.push_back({th1, base2 - a2, a3 - psi});
    arms.push_back({th1, base2 + a2, -a3 - psi});
  }
  for (const Arm& a : arms) {
    const double s1 = std::sin(a.th1), c1 = std::cos(a.th1), s23 = std::sin(a.th2 + a.th3), c23 = std::cos(a.th2 + a.th3);
    const double m = R.at(0, 2) * s23 * c1 + R.at(1, 2) * s23 * s1 + R.at(2, 2) * c23;
    const double th5 = std::atan2(std::sqrt(std::max(0.0, 1.0 - m * m)), m);
    const double th4 = std::atan2(R.at(1, 2) * c1 - R.at(0, 2) * s1, R.at(0, 2) * c23 * c1 + R.at(1, 2) * c23 * s1 - R.at(2, 2) * s23);
    const double th6 = std::atan2(R.at(0, 1) * s23 * c1 + R.at(1, 1) * s23 * s1 + R.at(2, 1) * c23,
                                  -R.at(0, 0) * s23 * c1 - R.at(1, 0) * s23 * s1 - R.at(2, 0) * c23);
    out.push_back({a.th1, a.th2, a.th3, th4, th5, th6});
    out.push_back({a.th1, a.th2, a.th3, th4 + std::numbers::pi, -th5, th6 - std::numbers::pi});
  }
  return out;
}

// Q's joint I shifted by whole turns into [MIN, MAX], nearest NEAR; false when no turn fits.
bool fit_turn(double& q, double lo, double hi, double near) {
  const double k0 = std::round((near - q) / 360.0);
  double best = NAN;
  for (int dk = -2; dk <= 2; ++dk) {
    const double v = q + 360.0 * (k0 + dk);
    if (v >= lo - kAxisLimitSlack && v <= hi + kAxisLimitSlack && (std::isnan(best) || std::abs(v - near) < std::abs(best - near))) best = v;
  }
  if (std::isnan(best)) return false;
  q = best;
  return true;
}

// The part-frame rotation at POSE's rotary axes (machine frame → part frame) and the part point
// of the machine-frame origin: forward() is affine in X Y Z.
struct Turn {
  Mat3 rot;
  Vec3 origin;
};
Turn positioner_turn(const MachineConfig& m, const MachinePose& pose) {
  MachinePose p = pose;
  p.x_mm = p.y_mm = p.z_mm = 0.0;
  const Vec3 o = forward(m, p).tip_part_mm;
  Turn t;
  t.origin = o;
  p.x_mm = 1.0;
  t.rot.c0 = forward(m, p).tip_part_mm - o;
  p.x_mm = 0.0, p.y_mm = 1.0;
  t.rot.c1 = forward(m, p).tip_part_mm - o;
  p.y_mm = 0.0, p.z_mm = 1.0;
  t.rot.c2 = forward(m, p).tip_part_mm - o;
  return t;
}

// The part frame in the world at POSE's rotary axes.
Frame3 part_in_world(const MachineConfig& m, const MachinePose& pose) {
  const Turn t = positioner_turn(m, pose);
  const Frame3 machine_to_part = frame(t.origin, t.rot);
  return compose(floor_frame(m.robot->positioner), inverted(machine_to_part));
}

std::string joint_range_text(const RobotCell& r, int i, double q) {
  return fmt::format("axis {} at {:.2f}° is outside [{}°, {}°]", i + 1, q, r.min_deg[static_cast<std::size_t>(i)], r.max_deg[static_cast<std::size_t>(i)]);
}

}  // namespace

Quaternion quaternion_of(const Frame3& f) {
  const Mat3 m = rotation(f);
  const double tr = m.at(0, 0) + m.at(1, 1) + m.at(2, 2);
  Quaternion q;
  if (tr > 0.0) {
    const double s = 2.0 * std::sqrt(1.0 + tr);
    q = {0.25 * s, (m.at(2, 1) - m.at(1, 2)) / s, (m.at(0, 2) - m.at(2, 0)) / s, (m.at(1, 0) - m.at(0, 1)) / s};
  } else if (m.at(0, 0) > m.at(1, 1) && m.at(0, 0) > m.at(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + m.at(0, 0) - m.at(1, 1) - m.at(2, 2));
    q = {(m.at(2, 1) - m.at(1, 2)) / s, 0.25 * s, (m.at(0, 1) + m.at(1, 0)) / s, (m.at(0, 2) + m.at(2, 0)) / s};
  } else if (m.at(1, 1) > m.at(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + m.at(1, 1) - m.at(0, 0) - m.at(2, 2));
    q = {(m.at(0, 2) - m.at(2, 0)) / s, (m.at(0, 1) + m.at(1, 0)) / s, 0.25 * s, (m.at(1, 2) + m.at(2, 1)) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m.at(2, 2) - m.at(0, 0) - m.at(1, 1));
    q = {(m.at(1, 0) - m.at(0, 1)) / s, (m.at(0, 2) + m.at(2, 0)) / s, (m.at(1, 2) + m.at(2, 1)) / s, 0.25 * s};
  }
  if (q.w < 0.0) q = {-q.w, -q.x, -q.y, -q.z};
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

Frame3 frame_of(Vec3 origin, Quaternion q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  const double w = q.w / n, x = q.x / n, y = q.y / n, z = q.z / n;
  return {origin,
          {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)},
          {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)},
          {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)}};
}

Frame3 robot_tcp_world(const RobotCell& r, const RobotJoints& q) {
  std::array<double, 6> th{};
  for (int i = 0; i < 6; ++i) th[static_cast<std::size_t>(i)] = model_rad(r, i, q[static_cast<std::size_t>(i)]);
  return compose(floor_frame(r.base), compose(flange_in_base(r, th), tool_frame(r)));
}

RobotConfiguration robot_configuration(const RobotCell& r, const RobotJoints& q) {
  std::array<double, 6> th{};
  for (int i = 0; i < 6; ++i) th[static_cast<std::size_t>(i)] = model_rad(r, i, q[static_cast<std::size_t>(i)]);
  const double k = std::hypot(r.a2_mm, r.c3_mm), psi = std::atan2(r.a2_mm, r.c3_mm);
  const double cx1 = r.c2_mm * std::sin(th[1]) + k * std::sin(th[1] + th[2] + psi) + r.a1_mm;
  const bool behind_axis1 = cx1 < 0.0;
  const bool behind_lower_arm = std::sin(th[2] + psi) < 0.0;  // the wrist centre's side of the lower arm's line
  RobotConfiguration c;
  c.cf1 = static_cast<int>(std::floor(q[0] / 90.0));
  c.cf4 = static_cast<int>(std::floor(q[3] / 90.0));
  c.cf6 = static_cast<int>(std::floor(q[5] / 90.0));
  c.cfx = 4 * static_cast<int>(behind_axis1) + 2 * static_cast<int>(behind_lower_arm) + static_cast<int>(q[4] < 0.0);
  return c;
}

std::vector<RobotSolution> robot_solutions(const RobotCell& r, const Frame3& tcp_world, const RobotJoints* near) {
  const Frame3 flange = compose(inverted(floor_frame(r.base)), compose(tcp_world, inverted(tool_frame(r))));
  std::vector<RobotSolution> out;
  for (const auto& th : model_solutions(r, flange)) {
    RobotSolution s;
    bool ok = true;
    for (std::size_t i = 0; i < 6 && ok; ++i) {
      double q = joint_deg(r, static_cast<int>(i), th[i]);
      ok = fit_turn(q, r.min_deg[i], r.max_deg[i], near != nullptr ? (*near)[i] : 0.0);
      s.q[i] = q;
    }
    if (!ok) continue;
    s.conf = robot_configuration(r, s.q);
    s.wrist_deg = std::abs(std::remainder(th[4], 2.0 * std::numbers::pi)) * kDegPerRad;
    out.push_back(s);
  }
  return out;
}

std::string robot_unreachable_reason(const RobotCell& r, const Frame3& tcp_world) {
  const Frame3 flange = compose(inverted(floor_frame(r.base)), compose(tcp_world, inverted(tool_frame(r))));
  const auto all = model_solutions(r, flange);
  const Vec3 w = tcp_world.origin;
  if (all.empty()) return fmt::format("out of the arm's reach: the TCP at ({:.1f}, {:.1f}, {:.1f}) mm in the world", w.x, w.y, w.z);
  std::string why;
  for (const auto& th : all) {
    for (std::size_t i = 0; i < 6; ++i) {
      double q = joint_deg(r, static_cast<int>(i), th[i]);
      if (!fit_turn(q, r.min_deg[i], r.max_deg[i], 0.0)) {
        if (why.empty()) why = joint_range_text(r, static_cast<int>(i), joint_deg(r, static_cast<int>(i), th[i]));
        break;
      }
    }
  }
  return fmt::format("every joint solution leaves a joint limit ({}, ...), the TCP at ({:.1f}, {:.1f}, {:.1f}) mm in the world", why, w.x, w.y, w.z);
}

Frame3 tcp_world_for(const MachineConfig& m, const MachinePose& pose, Vec3 tip_part, Vec3 axis_part) {
  const Frame3 part = part_in_world(m, pose);
  const Mat3 rp = rotation(part);
  const Vec3 tip = part.origin + rp * tip_part;
  const Vec3 z = core::normalized(rp * axis_part) * -1.0;
  const Frame3 base = floor_frame(m.robot->base);
  // x: toward the base's axis, horizontally, made square to z; along the base's −x when that is
  // (nearly) along z.
  Vec3 toward = Vec3{base.origin.x - tip.x, base.origin.y - tip.y, 0.0};
  Vec3 x = toward - z * core::dot(toward, z);
  if (core::norm(x) < 1e-6 * std::max(1.0, core::norm(toward))) {
    const Vec3 back = base.x * -1.0;
    x = back - z * core::dot(back, z);
    if (core::norm(x) < 1e-9) x = base.y - z * core::dot(base.y, z);
  }
  x = core::normalized(x);
  return {tip, x, core::cross(z, x), z};
}

Frame3 tcp_in_part(const MachineConfig& m, const MachinePose& pose, const Frame3& tcp_world) {
  return compose(inverted(part_in_world(m, pose)), tcp_world);
}

Frame3 tcp_in_world(const MachineConfig& m, const MachinePose& pose, const Frame3& tcp_part) {
  return compose(part_in_world(m, pose), tcp_part);
}

MachineToolPose part_tool_of(const MachineConfig& m, const MachinePose& pose, const Frame3& tcp_world) {
  const Frame3 f = tcp_in_part(m, pose, tcp_world);
  return {f.origin, f.z * -1.0};
}

MachinePose positioner_pose_for(const MachineConfig& m, MachinePose pose, Vec3 tip_part) {
  const Turn t = positioner_turn(m, pose);
  const Vec3 j = t.rot.transposed() * (tip_part - t.origin);
  pose.x_mm = j.x, pose.y_mm = j.y, pose.z_mm = j.z;
  return pose;
}

}  // namespace polyaxis::machine
