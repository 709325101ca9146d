#include "polyaxis/machine/segment.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <numbers>

namespace polyaxis::machine {

namespace {

// Tool axes closer than this (radians) are interpolated linearly instead of by slerp; an axis
// turning by more than π minus this has no defined path.
constexpr double kSlerpParallelRad = 1e-12;
constexpr double kReversedAxisRad = 1e-6;
// A piece that would leave less than this share of the smallest piece before the end goes to the end.
constexpr double kLastPieceShare = 0.5;
// Leaving the singular axis, C is read where the tilt is this many times the singular limit.
constexpr double kLeavePoleTilts = 16.0;
// An axis this close to a pole (radians), though off it, has an azimuth too ill-conditioned to
// follow: a move ending (or starting) there goes through the pole. The tip turns less than
// 0.0001 mm per mm from the C axis when C swings there.
constexpr double kAlmostPoleRad = 1e-4;
// Two axes whose azimuths differ by less than this (radians) lean the same way: C need not turn
// between them.
constexpr double kSameAzimuthRad = 1e-3;

Vec3 lerp(Vec3 a, Vec3 b, double s) { return a + (b - a) * s; }

MachinePose lerp(const MachinePose& a, const MachinePose& b, double u) {
  return {a.x_mm + (b.x_mm - a.x_mm) * u, a.y_mm + (b.y_mm - a.y_mm) * u, a.z_mm + (b.z_mm - a.z_mm) * u,
          a.a_or_b_deg + (b.a_or_b_deg - a.a_or_b_deg) * u, a.c_deg + (b.c_deg - a.c_deg) * u};
}

Vec3 slerp(Vec3 a, Vec3 b, double omega, double s) {
  if (omega < kSlerpParallelRad) return normalized(lerp(a, b, s));
  const double so = std::sin(omega);
  return a * (std::sin((1.0 - s) * omega) / so) + b * (std::sin(s * omega) / so);
}

// Where a move cannot be followed: the C that the pose at (TIP, AXIS) takes following FROM on a
// machine without end stops, when that is beyond MACHINE's end stops (the inverse kinematics then
// took the same orientation a turn away, or the other branch: a jump no piece of the move can make).
std::optional<double> past_end_stop(const MachineConfig& machine, Vec3 tip, Vec3 axis, const MachinePose& from) {
  if (!has_rotary_axes(machine.kind) || machine.c_continuous) return std::nullopt;
  MachineConfig free = machine;
  free.c_continuous = true;
  auto pose = inverse(free, tip, axis, &from);
  if (!pose) return std::nullopt;
  const double c = pose.value().c_deg;
  if (c >= machine.c_deg.min - kAxisLimitSlack && c <= machine.c_deg.max + kAxisLimitSlack) return std::nullopt;
  return c;
}

struct Subdivider {
  const MachineConfig& m;
  Vec3 p0, p1, t0, t1;
  double omega;
  double chordal_mm;
  std::vector<MachinePose>& out;
  // Turning C in place at a vertical tool axis: midpoints interpolate C (the IK holds C there).
  bool turn_c_in_place = false;

  // Largest sampled distance of the controller's tip from the part segment between parameters.
  double deviation(const MachinePose& a, double sa, const MachinePose& b, double sb) const {
    const Vec3 qa = lerp(p0, p1, sa), qb = lerp(p0, p1, sb);
    double worst = 0.0;
    for (const double u : {0.25, 0.5, 0.75}) {
      worst = std::max(worst, distance_to_segment(forward(m, lerp(a, b, u)).tip_part_mm, qa, qb));
    }
    return worst;
  }

  core::Status refine(const MachinePose& a, double sa, const MachinePose& b, double sb, int depth) {
    const double rotary = std::max(std::abs(b.a_or_b_deg - a.a_or_b_deg), std::abs(b.c_deg - a.c_deg));
    const double dev = deviation(a, sa, b, sb);
    if (dev <= chordal_mm && rotary <= kMaxRotaryStepDeg) {
      out.push_back(b);
      return {};
    }
    if (depth >= kMaxSubdivisionDepth) {
      return core::make_error(
          core::ErrorCode::kInfeasible,
          fmt::format("cannot keep the tip within {} mm turning C in place at ({:.4f}, {:.4f}, {:.4f}): {:.4f} mm off after "
                      "{} bisections",
                      chordal_mm, p0.x, p0.y, p0.z, dev, depth));
    }
    const double sm = 0.5 * (sa + sb);
    MachinePose hint = a;
    if (turn_c_in_place) hint.c_deg = 0.5 * (a.c_deg + b.c_deg);
    auto mid = inverse(m, lerp(p0, p1, sm), slerp(t0, t1, omega, sm), &hint);
    if (!mid) return mid.error();
    if (auto st = refine(a, sa, mid.value(), sm, depth + 1); !st) return st;
    return refine(mid.value(), sm, b, sb, depth + 1);
  }
};

}  // namespace

double distance_to_segment(Vec3 q, Vec3 a, Vec3 b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
  return norm(q - (a + ab * s));
}

core::Result<std::vector<MachinePose>> turn_c_in_place(const MachineConfig& machine, const MachinePose& start, double target_c_deg,
                                                       double chordal_mm) {
  std::vector<MachinePose> out;
  if (target_c_deg == start.c_deg) return out;
  const double tilt_rad = std::abs(start.a_or_b_deg) * std::numbers::pi / 180.0;
  if (!has_rotary_axes(machine.kind) ||
      !(tilt_rad < kSingularTiltRad || std::abs(tilt_rad - std::numbers::pi) < kSingularTiltRad)) {
    return core::make_error(core::ErrorCode::kInternal,
                            fmt::format("C can only turn in place with the tool along C, not at {}", format_pose(machine, start)));
  }
  const MachineToolPose at = forward(machine, start);
  MachinePose hint = start;
  hint.c_deg = target_c_deg;
  auto turned = inverse(machine, at.tip_part_mm, at.tool_axis_part, &hint);
  if (!turned) return turned.error();
  Subdivider turn{machine, at.tip_part_mm, at.tip_part_mm, at.tool_axis_part, at.tool_axis_part, 0.0, chordal_mm, out, true};
  if (auto st = turn.refine(start, 0.0, turned.value(), 1.0, 0); !st) return st.error();
  return out;
}

core::Result<std::vector<MachinePose>> subdivide(const MachineConfig& machine, Vec3 p0, Vec3 t0, Vec3 p1, Vec3 t1,
                                                 const MachinePose& start, double chordal_mm) {
  if (!(chordal_mm > 0.0) || !std::isfinite(chordal_mm)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("chordal tolerance {} mm must be > 0", chordal_mm));
  }
  t0 = normalized(t0);
  t1 = normalized(t1);
  const double omega = std::atan2(norm(cross(t0, t1)), dot(t0, t1));
  if (omega > std::numbers::pi - kReversedAxisRad) {
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("the tool axis reverses along the segment ({:.4f}, {:.4f}, {:.4f})-({:.4f}, {:.4f}, "
                                        "{:.4f}): no path between opposite axes",
                                        p0.x, p0.y, p0.z, p1.x, p1.y, p1.z));
  }
  if (has_rotary_axes(machine.kind)) {
    // Passing close by the singular axis: through it instead.
    for (const Vec3 pole : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
      const Vec3 n = cross(t0, t1);
      if (norm(n) < kSlerpParallelRad) break;
      const Vec3 un = normalized(n);
      const double off = std::asin(std::min(1.0, std::abs(dot(un, pole))));
      const Vec3 q = normalized(pole - un * dot(un, pole));
      const double a0 = std::atan2(norm(cross(t0, q)), dot(t0, q)), a1 = std::atan2(norm(cross(q, t1)), dot(q, t1));
      const double e0 = std::atan2(norm(cross(t0, pole)), dot(t0, pole)), e1 = std::atan2(norm(cross(t1, pole)), dot(t1, pole));
      // Also where an end lies within kPoleSnapRad of the pole, when the arc passes the pole
      // nearer than both ends, between them (an end a tenth of a degree off the pole on the far
      // side: C swings through most of a half turn in a piece too short to follow). An end on
      // the pole (a leg of this split) has no pass between.
      const bool passes = std::abs(a0 + a1 - omega) <= 1e-9 && off < std::min(e0, e1) && std::min(a0, a1) >= kSingularTiltRad;
      if (off == 0.0 || off >= kPoleSnapRad || !passes) continue;
      const Vec3 pm = lerp(p0, p1, a0 / omega);
      auto first = subdivide(machine, p0, t0, pm, pole, start, chordal_mm);
      if (!first) return first.error();
      auto second = subdivide(machine, pm, pole, p1, t1, first.value().back(), chordal_mm);
      if (!second) return second.error();
      first.value().insert(first.value().end(), second.value().begin(), second.value().end());
      return first;
    }
  }
  if (has_rotary_axes(machine.kind)) {
    // An end within kAlmostPoleRad of a pole but off it (tilt above kSingularTiltRad), the other
    // end off the pole too: that end's C is the azimuth of a tilt of microradians, which may be far
    // from the C the move has at the other end, and C would have to swing in a piece too short for
    // any step. The move goes through the pole itself instead: arriving, C is held there; leaving,
    // C turns in place first (below). Each leg has an end on the pole, so neither splits again.
    for (const Vec3 pole : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
      const double e0 = std::atan2(norm(cross(t0, pole)), dot(t0, pole)), e1 = std::atan2(norm(cross(t1, pole)), dot(t1, pole));
      auto almost = [](double e) { return e >= kSingularTiltRad && e < kAlmostPoleRad; };
      const bool split_at_end = almost(e1) && e0 >= kSingularTiltRad, split_at_start = almost(e0) && e1 >= kSingularTiltRad;
      if (!split_at_end && !split_at_start) continue;
      // Ends leaning the same way need no other C: the move is made as it is (a tilted layer
      // whose normal is 0.0057° off the vertical went through the pole at every point, turning in
      // place each time, and each turn stopped the process).
      const double turn = std::remainder(std::atan2(t1.y, t1.x) - std::atan2(t0.y, t0.x), 2.0 * std::numbers::pi);
      if (std::abs(turn) < kSameAzimuthRad) continue;
      const Vec3 pm = split_at_end ? p1 : p0;
      auto first = subdivide(machine, p0, t0, pm, pole, start, chordal_mm);
      if (!first) return first.error();
      auto second = subdivide(machine, pm, pole, p1, t1, first.value().empty() ? start : first.value().back(), chordal_mm);
      if (!second) return second.error();
      first.value().insert(first.value().end(), second.value().begin(), second.value().end());
      return first;
    }
  }
  std::vector<MachinePose> out;
  MachinePose from = start;
  // Leaving a singular axis (RELIABILITY O2: the tool along C, upright or upside down): C was
  // held at an arbitrary value, and the move needs another. Turning C while the tilt changes would
  // swing the tip far off the segment, so C turns first, in place, with the axis still along C and
  // the tip held at P0; then the tilt.
  const double start_tilt_rad = std::abs(start.a_or_b_deg) * std::numbers::pi / 180.0;
  const bool start_singular = start_tilt_rad < kSingularTiltRad || std::abs(start_tilt_rad - std::numbers::pi) < kSingularTiltRad;
  const double min_step = std::ldexp(1.0, -kMaxSubdivisionDepth);
  if (has_rotary_axes(machine.kind) && start_singular && omega > kSlerpParallelRad) {
    // C as the axis leaves: its azimuth, constant along a great circle from the pole, read where
    // the tilt is well clear of the singular limit (so that C is defined there).
    const double leave = std::clamp(kLeavePoleTilts * kSingularTiltRad / omega, min_step, 1.0);
    auto depart = inverse(machine, lerp(p0, p1, leave), slerp(t0, t1, omega, leave), &start);
    if (!depart) return depart.error();
    MachinePose hint = start;
    hint.c_deg = depart.value().c_deg;
    auto turned = inverse(machine, p0, t0, &hint);
    if (!turned) return turned.error();
    if (turned.value().c_deg != start.c_deg) {
      Subdivider turn{machine, p0, p0, t0, t0, 0.0, chordal_mm, out, true};
      if (auto st = turn.refine(start, 0.0, turned.value(), 1.0, 0); !st) return st.error();
      from = turned.value();
    }
  }
  // The move itself, left to right: each piece as long as the tolerance and the rotary step allow
  // (halved until they do, doubled after), its end pose followed from its start's, so the pose
  // never jumps to the other branch of the same axis (tilt negated, C a half turn away).
  const Subdivider sub{machine, p0, p1, t0, t1, omega, chordal_mm, out, false};
  MachinePose a = from;
  double sa = 0.0, step = 1.0;
  while (sa < 1.0) {
    double sb = sa + step >= 1.0 - kLastPieceShare * min_step ? 1.0 : sa + step;
    for (;;) {
      auto b = sb == 1.0 ? inverse(machine, p1, t1, &a) : inverse(machine, lerp(p0, p1, sb), slerp(t0, t1, omega, sb), &a);
      if (!b) return b.error();

      const double rotary = std::max(std::abs(b.value().a_or_b_deg - a.a_or_b_deg), std::abs(b.value().c_deg - a.c_deg));
      const double dev = sub.deviation(a, sa, b.value(), sb);
      if (dev <= chordal_mm && rotary <= kMaxRotaryStepDeg) {
        out.push_back(b.value());
        step = 2.0 * (sb - sa);
        sa = sb;
        a = b.value();
        break;
      }
      if (sb - sa <= min_step) {
        if (auto past = past_end_stop(machine, lerp(p0, p1, sb), slerp(t0, t1, omega, sb), a)) {
          return core::make_error(
              core::ErrorCode::kMachineLimit,
              fmt::format("C would run past its end stops [{}, {}] deg within the move ({:.4f}, {:.4f}, {:.4f})-({:.4f}, {:.4f}, "
                          "{:.4f}) turning the axis from ({:.4f}, {:.4f}, {:.4f}) to ({:.4f}, {:.4f}, {:.4f}): it must turn on to "
                          "{:.4f} deg, and the same orientation a turn away or on the other branch is not a move the tip can "
                          "follow; a C that turns further (machine limits.c) or a continuous C would make it",
                          machine.c_deg.min, machine.c_deg.max, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, t0.x, t0.y, t0.z, t1.x, t1.y, t1.z,
                          *past));
        }
        return core::make_error(
            core::ErrorCode::kInfeasible,
            fmt::format("cannot keep the tip within {} mm of the segment ({:.4f}, {:.4f}, {:.4f})-({:.4f}, {:.4f}, {:.4f}) "
                        "turning the axis from ({:.4f}, {:.4f}, {:.4f}) to ({:.4f}, {:.4f}, {:.4f}): {:.4f} mm off in a "
                        "piece of 1/{} of it",
                        chordal_mm, p0.x, p0.y, p0.z, p1.x, p1.y, p1.z, t0.x, t0.y, t0.z, t1.x, t1.y, t1.z, dev,
                        std::llround(1.0 / min_step)));
      }
      sb = sa + 0.5 * (sb - sa);
    }
  }
  return out;
}

}  // namespace polyaxis::machine
