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
// An arc that passes the reach by less than this keeps within it (rounding), radians.
constexpr double kReachSlackRad = 1e-9;
// Axes turned round within the reach keep this far inside it, and turn at most this far a step, radians.
constexpr double kReachInsideRad = 0.05 * kPi / 180.0;
constexpr double kReachStepRad = 1.0 * kPi / 180.0;
// least_layable_height_mm's plate: under a footprint this far each way from the plate's middle, mm
// (wider than any head).
constexpr double kWideFootprintMm = 500.0;

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

Vec3 axis_between(Vec3 a, Vec3 b, double u) { return slerp(core::normalized(a), core::normalized(b), u); }

double max_tilt_on_arc_rad(Vec3 a, Vec3 b) {
  a = core::normalized(a), b = core::normalized(b);
  const double w = angle(a, b);
  double min_z = std::min(a.z, b.z);
  const Vec3 side = b - a * core::dot(a, b);  // towards B, perpendicular to A
  if (w > 1e-12 && core::norm(side) > 1e-12) {
    // z along the arc: a.z·cos θ + c.z·sin θ = r·cos(θ − φ), least at θ = φ + π when that is on it.
    const Vec3 c = core::normalized(side);
    const double r = std::hypot(a.z, c.z), phi = std::atan2(c.z, a.z);
    double low = phi + kPi;
    while (low > w) low -= 2.0 * kPi;
    while (low < 0.0) low += 2.0 * kPi;
    if (low <= w) min_z = std::min(min_z, -r);
  }
  return std::acos(std::clamp(min_z, -1.0, 1.0));
}

std::vector<Vec3> axes_within_reach(Vec3 a, Vec3 b, double reach_rad) {
  a = core::normalized(a), b = core::normalized(b);
  if (max_tilt_on_arc_rad(a, b) <= reach_rad + kReachSlackRad) return {};
  const double ta = std::acos(std::clamp(a.z, -1.0, 1.0)), tb = std::acos(std::clamp(b.z, -1.0, 1.0));
  const double pa = std::atan2(a.y, a.x), pb = std::atan2(b.y, b.x);
  double dp = pb - pa;
  while (dp > kPi) dp -= 2.0 * kPi;
  while (dp < -kPi) dp += 2.0 * kPi;
  // Between the ends the tilt stays a little inside the reach, so that the short great-circle steps
  // (which dip by under 0.001° at 1°) do not pass it; the ends come in and go out along their
  // meridians, which do not dip.
  const double cap = reach_rad - kReachInsideRad;
  auto axis_at = [](double t, double p) { return Vec3{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)}; };
  std::vector<Vec3> out;
  if (ta > cap) out.push_back(axis_at(cap, pa));
  // The turn on the sphere is at most |Δtilt| + |Δazimuth|.
  const auto n = static_cast<int>(std::ceil((std::abs(tb - ta) + std::abs(dp)) / kReachStepRad));
  for (int k = 1; k < n; ++k) {
    const double u = static_cast<double>(k) / n;
    out.push_back(axis_at(std::min(ta + (tb - ta) * u, cap), pa + dp * u));
  }
  if (tb > cap) out.push_back(axis_at(cap, pb));
  return out;
}

void keep_travel_within_reach(std::vector<post::ProgramPoint>& program, double reach_rad) {
  if (reach_rad <= 0.0 || program.empty()) return;
  std::vector<post::ProgramPoint> out;
  out.reserve(program.size());
  out.push_back(program.front());
  for (std::size_t i = 1; i < program.size(); ++i) {
    const post::ProgramPoint& p = program[i];
    if (!p.process_on) {
      const post::ProgramPoint from = out.back();
      const std::vector<Vec3> axes = axes_within_reach(from.tool_axis_part, p.tool_axis_part, reach_rad);
      for (std::size_t k = 0; k < axes.size(); ++k) {
        post::ProgramPoint w = p;
        const double u = static_cast<double>(k + 1) / static_cast<double>(axes.size() + 1);
        w.tip_part_mm = from.tip_part_mm + (p.tip_part_mm - from.tip_part_mm) * u;
        w.tool_axis_part = axes[k];
        w.comment_if_new_block = k == 0 ? "turning within the tilt's reach" : "";
        out.push_back(std::move(w));
      }
    }
    out.push_back(p);
  }
  program = std::move(out);
}

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

double least_layable_height_mm(const machine::MachineConfig& m, const process::ProcessConfig& process, double tilt_rad, double clearance_mm) {
  // The plate under a footprint wider than the head (the process's size when it gives one): the
  // head over the plate's top, not beyond its edge, where the table lies lower.
  const machine::BuildModel model = machine::make_build_model(m, process, -kWideFootprintMm, -kWideFootprintMm, kWideFootprintMm, kWideFootprintMm);
  const double tilt = std::max(0.0, tilt_rad - toolpath::kMaxTiltRad);
  const machine::SubstratePlate& plate = model.substrate;
  const Vec3 tip{(plate.x_min_mm + plate.x_max_mm) / 2.0, (plate.y_min_mm + plate.y_max_mm) / 2.0, plate.top_z_mm};
  const double clear = machine::head_clearance_mm(model, tip, {std::sin(tilt), 0.0, std::cos(tilt)});
  return std::isfinite(clear) ? std::max(0.0, clearance_mm - clear) : 0.0;
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
