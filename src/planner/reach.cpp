#include "reach.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "polyaxis/machine/kinematics.h"
#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::planner::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
// 2^-18 of a turn of at most 180°: 0.0007°, below the resolution of a rotary axis (0.001°). The
// bisection keeps the end that clears, so a coarser one turns the torch a little further, never less.
constexpr int kBisections = 18;

double angle(Vec3 a, Vec3 b) { return std::atan2(core::norm(core::cross(a, b)), core::dot(a, b)); }

// The unit vector at fraction U of the great circle from A to B (unit, not opposite).
Vec3 slerp(Vec3 a, Vec3 b, double u) {
  const double w = angle(a, b);
  if (w < 1e-12) return a;
  const double s = std::sin(w);
  if (s < 1e-12) {  // opposite: turn through any perpendicular
    const Vec3 p = core::normalized(std::abs(a.x) < 0.9 ? core::cross(a, Vec3{1, 0, 0}) : core::cross(a, Vec3{0, 1, 0}));
    return core::normalized(a * std::cos(u * w) + p * std::sin(u * w));
  }
  return core::normalized(a * (std::sin((1.0 - u) * w) / s) + b * (std::sin(u * w) / s));
}

}  // namespace

double reach_rad(const machine::MachineConfig& m) {
  if (!machine::has_rotary_axes(m.kind)) return 0.0;
  const double lo = std::abs(m.tilt_deg.min), hi = std::abs(m.tilt_deg.max);
  const bool full_turn = m.c_continuous || m.c_deg.max - m.c_deg.min >= 360.0;
  const bool both_signs = m.tilt_deg.min < 0.0 && m.tilt_deg.max > 0.0;
  const double deg = full_turn ? std::max(lo, hi) : (both_signs ? std::min(lo, hi) : std::max(lo, hi));
  return deg * kPi / 180.0;
}

double direction_reach_rad(const machine::MachineConfig& m, const process::ProcessConfig& process) {
  const double tilt = reach_rad(m);
  if (!machine::tilts_head(m.kind)) return tilt;
  return std::min(tilt, process.off_vertical_max_deg * kPi / 180.0);
}

core::Status check_region_reach(const std::vector<PlanRegion>& placed, const machine::MachineConfig& m, const process::ProcessConfig& process) {
  const Vec3 up{0, 0, 1};
  const double reach = direction_reach_rad(m, process);
  const bool gravity = machine::tilts_head(m.kind) && process.off_vertical_max_deg * kPi / 180.0 < reach_rad(m);
  for (const PlanRegion& r : placed) {
    const double need = angle(core::normalized(r.direction), up);
    if (need <= reach + 1e-9) continue;
    const char letter = machine::tilt_axis_letter(m.kind);
    if (gravity) {
      return core::make_error(
          core::ErrorCode::kMachineLimit,
          fmt::format("region {}: its build direction ({:.3f}, {:.3f}, {:.3f}) is {:.1f} deg from vertical, but on the head-head machine "
                      "'{}' the part stays fixed and the process deposits at most {:.1f} deg off vertical (process "
                      "off_vertical_max_deg): a process that deposits further off vertical, a table-table machine or "
                      "--strategy single would make it buildable",
                      r.id, r.direction.x, r.direction.y, r.direction.z, need * 180.0 / kPi, m.name, process.off_vertical_max_deg));
    }
    return core::make_error(
        core::ErrorCode::kMachineLimit,
        fmt::format("region {}: its build direction ({:.3f}, {:.3f}, {:.3f}) on the table needs a tilt of {:.1f} deg, but {} reaches "
                    "{:.1f} deg (machine '{}', limits.{}): a machine with a wider tilt range, another root base or "
                    "--strategy single would make it reachable",
                    r.id, r.direction.x, r.direction.y, r.direction.z, need * 180.0 / kPi, letter == '\0' ? 'Z' : letter,
                    reach * 180.0 / kPi, m.name, letter == '\0' ? 'z' : static_cast<char>(letter - 'A' + 'a')));
  }
  return {};
}

core::Status check_region_travel(const std::vector<PlanRegion>& placed, const machine::MachineConfig& m) {
  for (const PlanRegion& r : placed) {
    core::Box3 box;
    for (const Vec3& v : r.mesh.vertices) box.add(v);
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner{k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z};
      auto pose = machine::inverse(m, corner, r.direction, nullptr);
      if (pose) continue;
      return core::make_error(core::ErrorCode::kMachineLimit,
                              fmt::format("region {}: built along ({:.3f}, {:.3f}, {:.3f}), its corner ({:.1f}, {:.1f}, {:.1f}) on the table "
                                          "is out of the machine's travel: {}; a machine with more travel (machine '{}', limits) would "
                                          "reach it",
                                          r.id, r.direction.x, r.direction.y, r.direction.z, corner.x, corner.y, corner.z,
                                          pose.error().message, m.name));
    }
  }
  return {};
}

bool guard_axis(const machine::MachineConfig& machine, const machine::BuildModel& model, double reach, double clearance_mm,
                double lift_mm, Vec3 tip, Vec3 d, Vec3& axis) {
  const Vec3 up{0, 0, 1};
  const Vec3 start = core::normalized(axis);
  auto ok = [&](Vec3 a) {
    return angle(a, up) <= reach + 1e-12 && machine::head_clearance_mm(model, tip, a, clearance_mm) >= clearance_mm &&
           machine::head_clearance_mm(model, tip + a * lift_mm, a, clearance_mm) >= clearance_mm && (tip + a * lift_mm).z >= 0.0 &&
           machine::reachable(machine, tip, a) && machine::reachable(machine, tip + a * lift_mm, a);
  };
  if (ok(start)) return true;
  // The furthest the axis may turn: to +Z, or as far as it stays within kMaxTiltRad of D.
  double u_max = 1.0;
  if (angle(slerp(start, up, 1.0), d) > toolpath::kMaxTiltRad) {
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < kBisections; ++k) {
      const double mid = 0.5 * (lo + hi);
      (angle(slerp(start, up, mid), d) <= toolpath::kMaxTiltRad ? lo : hi) = mid;
    }
    u_max = lo;
  }
  const Vec3 furthest = slerp(start, up, u_max);
  if (!ok(furthest)) {
    axis = furthest;
    return false;
  }
  double lo = 0.0, hi = u_max;
  for (int k = 0; k < kBisections; ++k) {
    const double mid = 0.5 * (lo + hi);
    (ok(slerp(start, up, mid)) ? hi : lo) = mid;
  }
  axis = slerp(start, up, hi);
  return true;
}

bool move_clear(const machine::BuildModel& model, double clearance_mm, Vec3 tip_from, Vec3 from, Vec3 tip_to, Vec3 to) {
  const Vec3 a = core::normalized(from), b = core::normalized(to);
  const double by_turn = std::ceil(angle(a, b) / (2.0 * kPi / 180.0)), by_length = std::ceil(core::norm(tip_to - tip_from));
  const int steps = static_cast<int>(std::clamp(std::max(by_turn, by_length), 1.0, 1000.0));
  for (int k = 0; k <= steps; ++k) {
    const double u = static_cast<double>(k) / steps;
    if (machine::head_clearance_mm(model, tip_from + (tip_to - tip_from) * u, slerp(a, b, u), clearance_mm) < clearance_mm) return false;
  }
  return true;
}

}  // namespace polyaxis::planner::detail
