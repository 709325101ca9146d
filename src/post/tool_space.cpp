#include "post/tool_space.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace polyaxis::post::detail {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

// A block turning the tool with the tip moving less than this (mm) turns it in place.
constexpr double kStillTipMm = 1e-6;
// A block slowed to an axis maximum is timed this much longer, for the rounding of its words.
constexpr double kLimitMargin = 1e-5;
// A deposit block whose axes would hold the tip below this share of its feed is split (above
// verify::kStallShare, 0.5, as the LinuxCNC post's kStallGuardShare).
constexpr double kStallGuardShare = 0.6;

class Loop {
 public:
  Loop(const machine::MachineConfig& m, const GcodeOptions& o, ToolSpaceDialect& d) : m_(m), o_(o), d_(d) {}

  core::Status run(std::span<const ProgramPoint> points) {
    d_.header();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const ProgramPoint& pt = points[i];
      if (!core::is_finite(pt.tip_part_mm) || !core::is_finite(pt.tool_axis_part) || !(core::norm(pt.tool_axis_part) > 0.0) ||
          !std::isfinite(pt.feed_mm_s) || !(pt.feed_mm_s > 0.0)) {
        return make_error(ErrorCode::kInternal, fmt::format("{}: a non-finite or zero value (feed {} mm/s)", where(i, pt), pt.feed_mm_s));
      }
      auto pose = d_.pose_of(pt, i == 0 ? nullptr : &prev_);
      if (!pose) return make_error(pose.error().code, fmt::format("{}: {}", where(i, pt), pose.error().message));
      if (!pt.comment_if_new_block.empty()) d_.comment(pt);
      const ProgramPoint* next = i + 1 < points.size() ? &points[i + 1] : nullptr;
      if (auto st = step(points, i, pose.value(), next); !st) return make_error(st.error().code, fmt::format("{}: {}", where(i, pt), st.error().message));
      prev_ = pose.value();
      if (o_.max_output_bytes != 0 && d_.size() > o_.max_output_bytes) {
        return make_error(ErrorCode::kOutput, fmt::format("the program exceeds {} bytes", o_.max_output_bytes));
      }
    }
    d_.switch_process(false);
    d_.footer(stall_splits_);
    return {};
  }

 private:
  core::Status step(std::span<const ProgramPoint> points, std::size_t i, const MachinePose& pose, const ProgramPoint* next) {
    const ProgramPoint& pt = points[i];
    if (i == 0) return d_.block(BlockKind::kFirst, pt, pose, 0.0, next);
    const Vec3 tip = written_tip(pt.tip_part_mm), vec = written_vector(pt.tool_axis_part);
    const double tip_mm = core::norm(tip - written_tip(points[i - 1].tip_part_mm));
    const bool turns = core::norm(vec - written_vector(points[i - 1].tool_axis_part)) > 0.0;
    if (tip_mm < kStillTipMm && !turns) {
      d_.switch_process(pt.process_on);  // nothing moves: the process state alone
      return {};
    }
    if (tip_mm < kStillTipMm) {
      // The tool turns in place: with the process off (nothing may be laid on one spot); the next
      // deposit move switches it on again.
      d_.switch_process(false);
      return d_.block(BlockKind::kTurnInPlace, pt, pose, 0.0, next);
    }
    const double feed = feed_mm_s(tip_mm, pt.feed_mm_s, pose);
    if (pt.process_on && turns && feed < kStallGuardShare * pt.feed_mm_s) {
      // The axes would hold the tip below the deposit feed with the process on (the stall verify
      // counts): the tool turns first, in place with the process off, then the bead is laid with
      // the new vector at its feed (as the LinuxCNC post's stall split).
      ProgramPoint turn = pt;
      turn.tip_part_mm = points[i - 1].tip_part_mm;
      turn.process_on = false;
      auto at_start = d_.pose_of(turn, &prev_);
      if (!at_start) return at_start.error();
      d_.switch_process(false);
      if (auto st = d_.block(BlockKind::kTurnInPlace, turn, at_start.value(), 0.0, &pt); !st) return st;
      prev_ = at_start.value();
      ++stall_splits_;
      d_.switch_process(true);
      return d_.block(BlockKind::kFeed, pt, pose, feed_mm_s(tip_mm, pt.feed_mm_s, pose), next);
    }
    d_.switch_process(pt.process_on);
    return d_.block(BlockKind::kFeed, pt, pose, feed, next);
  }

  // The tip's path feed (mm/s, rounded down to 0.01 mm/min) for a block of TIP_MM at the planned
  // FEED_MM_S, slowed until the axes (at both ends, as written) stay within the machine's maxima.
  double feed_mm_s(double tip_mm, double feed, const MachinePose& to) {
    const double joints_mm = std::hypot(to.x_mm - prev_.x_mm, to.y_mm - prev_.y_mm, to.z_mm - prev_.z_mm);
    const double turn_deg = std::max(std::abs(to.a_or_b_deg - prev_.a_or_b_deg), std::abs(to.c_deg - prev_.c_deg));
    double minutes = tip_mm / (60.0 * feed);
    const double linear = joints_mm / m_.feed.linear_max_mm_min, rotary = turn_deg / m_.feed.rotary_max_deg_min;
    if (linear > minutes || rotary > minutes) {
      minutes = std::max(linear, rotary) * (1.0 + kLimitMargin);
      if (o_.stats != nullptr) ++(linear >= rotary ? o_.stats->linear_limited : o_.stats->rotary_limited);
    }
    // (The small addend keeps an exact quotient such as 30000 from flooring to 29999.)
    return std::max(0.1, std::floor(10.0 * tip_mm / minutes + 1e-9) / 10.0) / 60.0;
  }

  const machine::MachineConfig& m_;
  const GcodeOptions& o_;
  ToolSpaceDialect& d_;
  MachinePose prev_{};
  std::uint64_t stall_splits_ = 0;
};

}  // namespace

Vec3 written_tip(Vec3 p) { return {std::round(p.x * 1e4) / 1e4, std::round(p.y * 1e4) / 1e4, std::round(p.z * 1e4) / 1e4}; }
Vec3 rounded_vector(Vec3 a) {
  a = core::normalized(a);
  return Vec3{std::round(a.x * 1e6) / 1e6, std::round(a.y * 1e6) / 1e6, std::round(a.z * 1e6) / 1e6};
}
Vec3 written_vector(Vec3 a) { return core::normalized(rounded_vector(a)); }

std::string comment_text(std::string_view s) {
  std::string out;
  for (const char ch : s) out += ch < 0x20 || ch > 0x7e ? '?' : ch;
  return out;
}

std::string where(std::size_t i, const ProgramPoint& p) {
  return fmt::format("move to point {} (layer {} region {}, tip ({:.4f}, {:.4f}, {:.4f}), axis ({:.4f}, {:.4f}, {:.4f}))", i, p.layer, p.region,
                     p.tip_part_mm.x, p.tip_part_mm.y, p.tip_part_mm.z, p.tool_axis_part.x, p.tool_axis_part.y, p.tool_axis_part.z);
}

void GcodeDialect::switch_process(bool on) {
  if (on == on_) return;
  line(on ? p_.process_on : p_.process_off);
  if (on && p_.dwell_on_s > 0.0) line(dwell_block(p_.dwell_on_s));
  on_ = on;
}

std::string GcodeDialect::feed_word(double feed_mm_s) {
  if (o_.stats != nullptr) ++o_.stats->feed_blocks;
  const double f = std::round(600.0 * feed_mm_s) / 10.0;  // mm/min, as the loop rounded it down
  const bool same = last_feed_ && f == *last_feed_;
  last_feed_ = f;
  return same ? std::string() : fmt::format(" F{:.1f}", f);
}

core::Result<std::string> write_oriented(std::string_view what, const machine::MachineConfig& machine, std::span<const ProgramPoint> points,
                                         const GcodeOptions& options, GcodeDialect& dialect) {
  if (points.empty()) return make_error(ErrorCode::kInfeasible, "no program points to write");
  if (!machine::has_rotary_axes(machine.kind)) {
    return make_error(ErrorCode::kUsage, fmt::format("{} needs a 5-axis machine; '{}' is {}", what, machine.name, machine::kinematics_name(machine.kind)));
  }
  if (auto st = write_tool_space(machine, points, options, dialect); !st) return st.error();
  return dialect.take();
}

core::Status write_tool_space(const machine::MachineConfig& machine, std::span<const ProgramPoint> points, const GcodeOptions& options,
                              ToolSpaceDialect& dialect) {
  Loop loop(machine, options, dialect);
  return loop.run(points);
}

}  // namespace polyaxis::post::detail
