#include "polyaxis/verify/simulate.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>

#include "polyaxis/core/progress.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/segment.h"
#include "build_time.h"
#include "gcode_walk.h"

namespace polyaxis::verify {

namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// Plan segments searched ahead of the last match: generous for subdivided moves, keeps cost linear.
constexpr std::size_t kPlanWindow = 64;
// Consecutive planned segments a sample may lie on at once (zero-length turns in place among them).
constexpr std::size_t kSharedSegments = 8;
// Path length: a block is measured in pieces turning at most this much (degrees) each.
constexpr double kLengthStepDeg = 1.0;
// A feed above a limit by less than this fraction is the limit written with 4 decimals.
constexpr double kFeedLimitSlack = 1e-9;

// Angle (radians) from unit V to the great-circle arc from A to B (unit vectors).
double angle_to_arc(Vec3 v, Vec3 a, Vec3 b) {
  auto angle = [](Vec3 p, Vec3 q) { return std::atan2(norm(cross(p, q)), dot(p, q)); };
  const Vec3 n = cross(a, b);
  const double nn = norm(n);
  const double ends = std::min(angle(v, a), angle(v, b));
  if (nn < 1e-12) return ends;
  const Vec3 un = n / nn;
  const Vec3 w = v - un * dot(v, un);
  if (norm(w) < 1e-15) return ends;
  // W lies on the arc when it is between A and B as seen along N.
  if (dot(cross(a, w), un) >= 0.0 && dot(cross(w, b), un) >= 0.0) return std::asin(std::min(1.0, std::abs(dot(v, un))));
  return ends;
}

class PlanMatcher {
 public:
  PlanMatcher(std::span<const post::ProgramPoint> plan, double tolerance_mm) : plan_(plan), tolerance_mm_(tolerance_mm) {}

  // Deviation of a sample (tip, axis) from the plan: the earliest segment at or after the last
  // match (within a window) that the sample lies on within the path tolerance matches, and the
  // match moves there; a sample on none is measured against the nearest segment in the window and
  // the match stays where it was, so one stray sample cannot carry it past the path it belongs to.
  std::pair<double, double> deviation(Vec3 tip, Vec3 axis) {
    if (plan_.size() == 1) {
      const Vec3 a = normalized(plan_[0].tool_axis_part);
      return {norm(tip - plan_[0].tip_part_mm), std::atan2(norm(cross(axis, a)), dot(axis, a))};
    }
    const std::size_t segments = plan_.size() - 1;
    const std::size_t end = std::min(segments, cursor_ + kPlanWindow);
    double best = INFINITY;
    std::size_t best_j = cursor_;
    bool on_path = false;
    for (std::size_t j = cursor_; j < end; ++j) {
      const double d = machine::distance_to_segment(tip, plan_[j].tip_part_mm, plan_[j + 1].tip_part_mm);
      if (d <= tolerance_mm_) {
        best = d, best_j = j, on_path = true;
        break;
      }
      if (d < best) best = d, best_j = j;
    }
    auto arc_angle = [&](std::size_t j) {
      return angle_to_arc(axis, normalized(plan_[j].tool_axis_part), normalized(plan_[j + 1].tool_axis_part));
    };
    double ang = arc_angle(best_j);
    if (on_path) {
      cursor_ = best_j;
      // A sample where consecutive segments meet (a turn in place, the end of a path) lies on each
      // of them: its axis is measured against whichever of them it follows. A turn in place a
      // little farther than the tolerance (the sample already on its way along the next segment)
      // does not end the search: the next segment is what the sample follows.
      for (std::size_t j = best_j + 1; j < end && j < best_j + kSharedSegments; ++j) {
        if (machine::distance_to_segment(tip, plan_[j].tip_part_mm, plan_[j + 1].tip_part_mm) > tolerance_mm_) {
          if (plan_[j].tip_part_mm == plan_[j + 1].tip_part_mm) continue;
          break;
        }
        ang = std::min(ang, arc_angle(j));
      }
    }
    return {best, ang};
  }

 private:
  std::span<const post::ProgramPoint> plan_;
  double tolerance_mm_;
  std::size_t cursor_ = 0;
};

void widen(AxisSpan& s, double v) {
  s.min = std::min(s.min, v);
  s.max = std::max(s.max, v);
}

}  // namespace

core::Result<SimulationReport> simulate(const machine::MachineConfig& m, std::string_view gcode,
                                        std::span<const post::ProgramPoint> plan, const process::ProcessConfig* process,
                                        double path_tolerance_mm) {
  SimulationReport rep;
  rep.compared_with_plan = !plan.empty();
  PlanMatcher matcher(plan, path_tolerance_mm);
  const bool five = machine::has_rotary_axes(m.kind);

  auto violation = [&](std::uint64_t line_no, const std::string& what) {
    ++rep.limit_violations;
    if (rep.violations.size() < kMaxReportedViolations) rep.violations.push_back(fmt::format("line {}: {}", line_no, what));
  };
  auto sample = [&](std::uint64_t line_no, const machine::MachineToolPose& tp) {
    if (!rep.compared_with_plan) return;
    const auto [d_tip, d_axis] = matcher.deviation(tp.tip_part_mm, tp.tool_axis_part);
    if (d_tip > rep.max_tip_deviation_mm) {
      rep.max_tip_deviation_mm = d_tip;
      rep.worst_tip_line = line_no;
    }
    rep.max_axis_deviation_deg = std::max(rep.max_axis_deviation_deg, d_axis * kDegPerRad);
  };
  core::Progress progress("simulate", 0);
  detail::BuildTimer timer(m);
  detail::WalkCallbacks cb;
  cb.dwell = [&](std::uint64_t, double seconds, bool) { timer.dwell(seconds); };
  cb.target = [&](std::uint64_t line_no, const MachinePose& target, std::string_view) {
    widen(rep.x_mm, target.x_mm);
    widen(rep.y_mm, target.y_mm);
    widen(rep.z_mm, target.z_mm);
    if (five) {
      widen(rep.a_or_b_deg, target.a_or_b_deg);
      widen(rep.c_deg, target.c_deg);
    }
    if (std::string v = machine::limit_violation(m, target); !v.empty()) violation(line_no, v);
  };
  cb.move = [&](const detail::WalkMove& mv) {
    if ((rep.moves & 4095) == 0) progress.update(rep.moves);
    ++rep.moves;
    if (mv.rapid) ++rep.rapid_moves;
    if (!mv.from_known) {
      sample(mv.line, detail::tool_at(m, mv, 1.0));
      return;
    }
    const double d_tilt = mv.d_tilt_deg, d_c = mv.d_c_deg, l_xyz = mv.l_xyz_mm;
    timer.move(mv);
    if (!mv.rapid) {
      const double t_min = mv.time_min;
      rep.feed_time_s += t_min * 60.0;
      if (l_xyz / t_min > m.feed.linear_max_mm_min * (1.0 + kFeedLimitSlack)) {
        violation(mv.line, fmt::format("XYZ feed {:.4f} mm/min is above the maximum {} mm/min", l_xyz / t_min,
                                       m.feed.linear_max_mm_min));
      }
      // F of a rotary-only G-code block is its angular feed; a tool-space block's axes turn as
      // the controller's kinematics make them in the block's time.
      const double rot_speed = (l_xyz > 0.0 || mv.inverse_time || mv.tool_space) ? std::max(d_tilt, d_c) / t_min : mv.feed;
      if (rot_speed > m.feed.rotary_max_deg_min * (1.0 + kFeedLimitSlack)) {
        violation(mv.line, fmt::format("rotary feed {:.4f} deg/min is above the maximum {} deg/min", rot_speed,
                                       m.feed.rotary_max_deg_min));
      }
    }
    const int pieces = 1 + static_cast<int>(std::ceil(std::max(d_tilt, d_c) / kLengthStepDeg));
    Vec3 last_tip = detail::tool_at(m, mv, 0.0).tip_part_mm;
    double length = 0.0;
    for (int k = 1; k <= pieces; ++k) {
      const Vec3 tip = detail::tool_at(m, mv, static_cast<double>(k) / pieces).tip_part_mm;
      length += norm(tip - last_tip);
      last_tip = tip;
    }
    rep.path_length_mm += length;
    if (mv.process_on) rep.deposit_length_mm += length;
    for (const double u : {0.25, 0.5, 0.75, 1.0}) sample(mv.line, detail::tool_at(m, mv, u));
  };
  if (auto st = detail::walk_gcode(m, gcode, process, cb, &rep.program_end); !st) return st.error();
  rep.build_time = timer.finish();
  return rep;
}

}  // namespace polyaxis::verify
