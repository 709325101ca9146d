#include "polyaxis/post/gcode.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <vector>

#include "polyaxis/core/progress.h"
#include "polyaxis/io/write_file.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/segment.h"

namespace polyaxis::post {

namespace {

// Share of the chordal tolerance given to subdivision; the rest absorbs the rounding of the words.
constexpr double kSubdivisionShare = 0.8;
// A deposit block slower than this share of the deposit feed is split into a turn in place with
// the process off and a bead at the new axis; above verify::kStallShare (0.5), so that the words'
// rounding cannot bring a block the writer kept under the verifier's limit.
constexpr double kStallGuardShare = 0.6;
// Consecutive program points whose tilt changes sign while C moves more than this (degrees) are on
// different solution branches (a pass by the singular axis keeps C).
constexpr double kBranchJumpDeg = 90.0;
// A block whose axis limits lengthen it by more than this share of its planned time is counted as
// slowed (GcodeStats).
constexpr double kSlowedShare = 0.01;

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

// Words have 4 decimals: 0.1 µm and 0.0001°, the resolution rs274 prints and far below deposition.
constexpr double kWordScale = 1e4;
// Any axis value beyond this is refused as a broken invariant before it becomes a word.
constexpr double kMaxWordMagnitude = 1e9;

// A pose as the integers of its words (value · 1e4), which is what the controller reads.
using Words = std::array<std::int64_t, 5>;


// fixed4(N) appended to OUT without a format string (the writer's inner loop).
void append_fixed4(std::string& out, std::int64_t n) {
  const std::uint64_t a = n < 0 ? static_cast<std::uint64_t>(-(n + 1)) + 1 : static_cast<std::uint64_t>(n);
  if (n < 0) out += '-';
  char digits[24];
  auto [end, ec] = std::to_chars(digits, digits + sizeof digits, a / 10000);
  out.append(digits, end);
  const auto frac = static_cast<unsigned>(a % 10000);
  const char f[5] = {'.', static_cast<char>('0' + frac / 1000), static_cast<char>('0' + frac / 100 % 10),
                     static_cast<char>('0' + frac / 10 % 10), static_cast<char>('0' + frac % 10)};
  out.append(f, 5);
}

double value_of(std::int64_t n) { return static_cast<double>(n) / kWordScale; }

// Rounds V to a word, staying inside [LO, HI] (rounding never pushes a value past a soft limit).
bool to_word(double v, double lo, double hi, bool clamp, std::int64_t& out) {
  if (!std::isfinite(v) || std::abs(v) > kMaxWordMagnitude) return false;
  std::int64_t n = std::llround(v * kWordScale);
  if (clamp) {
    const auto hi_n = static_cast<std::int64_t>(std::floor(hi * kWordScale + 1e-6));
    const auto lo_n = static_cast<std::int64_t>(std::ceil(lo * kWordScale - 1e-6));
    if (n > hi_n && v <= hi + machine::kAxisLimitSlack) n = hi_n;
    if (n < lo_n && v >= lo - machine::kAxisLimitSlack) n = lo_n;
  }
  out = n;
  return true;
}

MachinePose pose_of(const Words& w) {
  return {value_of(w[0]), value_of(w[1]), value_of(w[2]), value_of(w[3]), value_of(w[4])};
}

// F rounded down (never above the value that respects the limits) with at least 4 significant
// digits; "" when it would round to zero.
std::string feed_word(double f) {
  int decimals = 1;
  if (f < 100.0) decimals = 3;
  if (f < 1.0) decimals = std::min(12, 4 + static_cast<int>(std::ceil(-std::log10(f))));
  const double scale = std::pow(10.0, decimals);
  const auto n = static_cast<std::int64_t>(std::floor(f * scale));
  if (n <= 0) return {};
  const auto un = static_cast<std::uint64_t>(n);
  const auto us = static_cast<std::uint64_t>(std::llround(scale));
  return fmt::format("{}.{:0{}d}", un / us, un % us, decimals);
}

// Comment text is free text from configs and the toolpath: nothing may close the comment early,
// start another or leave the line.
std::string sanitize_comment(std::string_view s) {
  std::string out;
  for (const char ch : s) {
    if (ch == '(') out += '[';
    else if (ch == ')') out += ']';
    else if (ch == ';') out += ',';
    else if (ch < 0x20 || ch > 0x7e) out += '?';
    else out += ch;
  }
  return out;
}

// Which move a message is about; rendered only when there is a message.
struct Where {
  std::size_t i;
  const ProgramPoint* pt;
  std::string str() const {
    return fmt::format("move to point {} (layer {} region {}, tip ({:.4f}, {:.4f}, {:.4f}), axis ({:.4f}, {:.4f}, {:.4f}))", i,
                       pt->layer, pt->region, pt->tip_part_mm.x, pt->tip_part_mm.y, pt->tip_part_mm.z, pt->tool_axis_part.x,
                       pt->tool_axis_part.y, pt->tool_axis_part.z);
  }
};

class Writer {
 public:
  Writer(const machine::MachineConfig& m, const GcodeOptions& o) : m_(m), o_(o), five_(machine::has_rotary_axes(m.kind)) {}

  void line(std::string_view s) {
    out_ += s;
    out_ += '\n';
  }

  // One block to POSE; MOTION is "G0" or "G1"; FEED_MM_S is the planned tip speed (G1 only).
  core::Status move(const MachinePose& pose, bool rapid, double feed_mm_s, const Where& where) {
    Words w{};
    const std::array<double, 5> v{pose.x_mm, pose.y_mm, pose.z_mm, pose.a_or_b_deg, pose.c_deg};
    const std::array<machine::AxisRange, 5> r{m_.x_mm, m_.y_mm, m_.z_mm, m_.tilt_deg, m_.c_deg};
    const std::array<char, 5> letter{'X', 'Y', 'Z', machine::tilt_axis_letter(m_.kind), 'C'};
    const int n_axes = five_ ? 5 : 3;
    for (int k = 0; k < n_axes; ++k) {
      const bool clamp = !(k == 4 && m_.c_continuous);
      if (!to_word(v[k], r[k].min, r[k].max, clamp, w[k])) {
        return make_error(ErrorCode::kInternal, fmt::format("{}: {} would be {} (not a finite number)", where.str(), letter[k], v[k]));
      }
    }
    if (have_last_ && w == last_) return {};  // nothing moves at the words' resolution
    const MachinePose target = pose_of(w);
    // Soft limits once more on the words themselves (the IK checked the exact values).
    if (std::string bad = machine::limit_violation(m_, target); !bad.empty()) {
      return make_error(ErrorCode::kMachineLimit, fmt::format("{}: {} in {}", where.str(), bad, machine::format_pose(m_, target)));
    }
    std::string block = rapid ? "G0" : "G1";
    for (int k = 0; k < n_axes; ++k) {
      block += ' ';
      block += letter[k];
      append_fixed4(block, w[k]);
    }
    if (!rapid) {
      if (!have_last_) {
        return make_error(ErrorCode::kInternal, fmt::format("{}: a feed move without a known start", where.str()));
      }
      std::string f = feed(last_, w, feed_mm_s);
      if (f.empty()) {
        return make_error(ErrorCode::kInternal, fmt::format("{}: the feed rounds to zero in {}", where.str(), block));
      }
      if (f != last_feed_) {
        block += " F" + f;
        last_feed_ = std::move(f);
      }
    }
    line(block);
    last_ = w;
    have_last_ = true;
    return {};
  }

  bool over_cap() const { return o_.max_output_bytes != 0 && out_.size() > o_.max_output_bytes; }
  std::string take() { return std::move(out_); }

 private:
  // Feed word for the block A → B (see the header for LinuxCNC's reading of F).
  std::string feed(const Words& a, const Words& b, double feed_mm_s) const {
    const MachinePose pa = pose_of(a), pb = pose_of(b);
    const double l_part = norm(machine::forward(m_, pb).tip_part_mm - machine::forward(m_, pa).tip_part_mm);
    const double l_xyz = norm(Vec3{pb.x_mm - pa.x_mm, pb.y_mm - pa.y_mm, pb.z_mm - pa.z_mm});
    const double d_tilt = std::abs(pb.a_or_b_deg - pa.a_or_b_deg), d_c = std::abs(pb.c_deg - pa.c_deg);
    const double l_rot = std::hypot(d_tilt, d_c);
    // Duration in minutes: the planned tip speed, slowed until every axis is within its maximum.
    const double t_feed = l_part / (feed_mm_s * 60.0), t_linear = l_xyz / m_.feed.linear_max_mm_min;
    const double t_rotary = std::max(d_tilt, d_c) / m_.feed.rotary_max_deg_min;
    double t_min = std::max({t_feed, t_linear, t_rotary});
    ++stats_.feed_blocks;
    // Slowed by more than the words' rounding: counted.
    if (t_min > t_feed * (1.0 + kSlowedShare)) ++(t_linear >= t_rotary ? stats_.linear_limited : stats_.rotary_limited);
    if (l_xyz > 0.0) return feed_word(l_xyz / t_min);
    // Rotary only: F is degrees/min along the combined rotary motion, itself within the rotary maximum.
    t_min = std::max(t_min, l_rot / m_.feed.rotary_max_deg_min);
    return feed_word(l_rot / t_min);
  }

  const machine::MachineConfig& m_;
  const GcodeOptions& o_;

 public:
  mutable GcodeStats stats_;

 private:
  const bool five_;
  std::string out_;
  Words last_{};
  bool have_last_ = false;
  std::string last_feed_;
};

// True when a block of POSES (from PREV) would leave the tip below kStallGuardShare of FEED_MM_S
// because a rotary or linear axis limit sets its duration.
bool stalls(const machine::MachineConfig& m, const MachinePose& prev, const std::vector<MachinePose>& poses, double feed_mm_s) {
  MachinePose a = prev;
  Vec3 tip_a = machine::forward(m, a).tip_part_mm;
  for (const MachinePose& b : poses) {
    const Vec3 tip_b = machine::forward(m, b).tip_part_mm;
    const double l_part = norm(tip_b - tip_a);
    const double l_xyz = norm(Vec3{b.x_mm - a.x_mm, b.y_mm - a.y_mm, b.z_mm - a.z_mm});
    const double rot = std::max(std::abs(b.a_or_b_deg - a.a_or_b_deg), std::abs(b.c_deg - a.c_deg));
    const double t_s = std::max({l_part / feed_mm_s, l_xyz / (m.feed.linear_max_mm_min / 60.0), rot / (m.feed.rotary_max_deg_min / 60.0)});
    if (t_s > 0.0 && l_part / t_s < kStallGuardShare * feed_mm_s) return true;
    a = b;
    tip_a = tip_b;
  }
  return false;
}

// How far C sweeps (degrees, relative to START's C) along POINTS[FROM..] up to the next unwind
// point, following the inverse kinematics from point to point as the writer will, with C free of
// end stops; COMPLETE is false where a point has no solution (the writer then reports it).
struct CSweep {
  double lo_deg = 0.0, hi_deg = 0.0;
  bool complete = true;
};

CSweep c_sweep(const machine::MachineConfig& m, std::span<const ProgramPoint> points, std::size_t from, const MachinePose& start) {
  machine::MachineConfig free_c = m;
  free_c.c_continuous = true;
  MachinePose pose = start;
  CSweep sweep;
  for (std::size_t j = from; j < points.size() && !points[j].c_unwind; ++j) {
    auto next = machine::inverse(free_c, points[j].tip_part_mm, points[j].tool_axis_part, &pose);
    if (!next) return sweep.complete = false, sweep;
    pose = next.value();
    sweep.lo_deg = std::min(sweep.lo_deg, pose.c_deg - start.c_deg);
    sweep.hi_deg = std::max(sweep.hi_deg, pose.c_deg - start.c_deg);
  }
  return sweep;
}

// The C to turn to at an unwind point (START has the tool along C, so any C holds the tool's
// orientation): whole turns from START's C, or a half turn more, which makes the next move leave
// on the other branch (tilt negated). The first whose sweep to the next unwind point fits the
// range (machine::unwound_c_deg), the nearer one when both fit; kMachineLimit when neither fits a
// limited C.
core::Result<double> unwind_target_deg(const machine::MachineConfig& m, std::span<const ProgramPoint> points, std::size_t from,
                                       const MachinePose& start) {
  CSweep first;
  double best = start.c_deg;
  bool best_fits = false, have = false;
  for (const double half : {0.0, 180.0}) {
    MachinePose s = start;
    s.c_deg += half;
    const CSweep sweep = c_sweep(m, points, from, s);
    if (half == 0.0) first = sweep;
    if (!sweep.complete && have) continue;
    const double c = machine::unwound_c_deg(m, s.c_deg, sweep.lo_deg, sweep.hi_deg);
    const bool fits = sweep.complete && (m.c_continuous || (c + sweep.lo_deg >= m.c_deg.min - machine::kAxisLimitSlack &&
                                                             c + sweep.hi_deg <= m.c_deg.max + machine::kAxisLimitSlack));
    if (!have || (fits && !best_fits) || (fits == best_fits && std::abs(c - start.c_deg) < std::abs(best - start.c_deg))) {
      best = c, best_fits = fits, have = true;
    }
  }
  if (!best_fits && !m.c_continuous) {
    return make_error(ErrorCode::kMachineLimit,
                      fmt::format("unwinding C: up to the next unwind point C sweeps from {:.1f}° to {:.1f}° relative to here, and "
                                  "no start ({:.1f}° plus whole or half turns) keeps that inside C's range [{}, {}]",
                                  first.lo_deg, first.hi_deg, start.c_deg, m.c_deg.min, m.c_deg.max));
  }
  return best;
}

// MESSAGE, or why it failed when the move from PREV to PT takes C past an end stop (the inverse
// kinematics then wraps C a whole turn, which no straight move follows).
std::string end_stop_or(const machine::MachineConfig& m, const MachinePose& prev, const ProgramPoint& pt, const std::string& message) {
  if (m.c_continuous || !machine::has_rotary_axes(m.kind)) return message;
  machine::MachineConfig free_c = m;
  free_c.c_continuous = true;
  auto free = machine::inverse(free_c, pt.tip_part_mm, pt.tool_axis_part, &prev);
  if (!free || (free.value().c_deg >= m.c_deg.min && free.value().c_deg <= m.c_deg.max)) return message;
  return fmt::format("C would reach {:.1f}°, beyond its range [{}, {}]: the tool axis winds round the vertical here; unwind "
                     "points (the tool upright with the process off) must come before it can turn back",
                     free.value().c_deg, m.c_deg.min, m.c_deg.max);
}

bool singular(const MachinePose& pose) {
  const double t = std::abs(pose.a_or_b_deg) * std::numbers::pi / 180.0;
  return t < machine::kSingularTiltRad || std::abs(t - std::numbers::pi) < machine::kSingularTiltRad;
}

// How many of POINTS[FROM..] the inverse kinematics follows from START on one solution branch, up
// to the next point where the tool is along C (where the branch may change freely): it stops at a
// point with no solution, or where it would have to jump to the other branch (tilt negated, C
// half a turn away), which no straight move can do.
std::size_t branch_reach(const machine::MachineConfig& m, std::span<const ProgramPoint> points, std::size_t from,
                         const MachinePose& start) {
  MachinePose pose = start;
  std::size_t j = from;
  for (; j < points.size(); ++j) {
    auto next = machine::inverse(m, points[j].tip_part_mm, points[j].tool_axis_part, &pose);
    if (!next) break;
    const MachinePose& q = next.value();
    const bool flipped = pose.a_or_b_deg * q.a_or_b_deg < 0.0 && std::abs(q.c_deg - pose.c_deg) > kBranchJumpDeg;
    if (flipped) break;
    pose = q;
    if (singular(pose) || points[j].c_unwind) return points.size();  // the rest is another stretch
  }
  return j;
}

// The solution branch to follow from a pose where it can be chosen (the first point, or the tool
// along C with the process off): the graph of candidate solutions along the program has two
// branches per point, joined only where the tool is along C, so the search compares the two
// branches over the stretch up to the next such point and keeps the one that goes furthest
// (the candidates' order breaks ties: the least rotary motion first).
MachinePose pick_branch(const machine::MachineConfig& m, std::span<const ProgramPoint> points, std::size_t from,
                        const std::vector<MachinePose>& candidates) {
  MachinePose best = candidates.front();
  std::size_t best_reach = 0;
  for (const MachinePose& c : candidates) {
    const std::size_t reach = branch_reach(m, points, from, c);
    if (reach > best_reach) best = c, best_reach = reach;
    if (reach == points.size()) break;
  }
  return best;
}

// PREV (the tool along C) with C a half turn further inside the limits: the next move leaves on
// the other branch.
std::optional<MachinePose> other_branch_at_pole(const machine::MachineConfig& m, const MachinePose& prev) {
  for (const double half : {180.0, -180.0}) {
    MachinePose q = prev;
    q.c_deg += half;
    if (machine::limit_violation(m, q).empty()) return q;
  }
  return std::nullopt;
}

// Writing a program point by point, in stages: the first pose, leaving the singular axis where the
// branch is free, the move itself (with a stall split), and an unwind.
class ProgramWriter {
 public:
  ProgramWriter(const machine::MachineConfig& m, const process::ProcessConfig& p, std::span<const ProgramPoint> points, const GcodeOptions& o)
      : m_(m), p_(p), points_(points), o_(o), w_(m, o), tol_(o.chordal_mm * kSubdivisionShare) {}

  Writer& out() { return w_; }

  // The first point: a rapid to the branch that gets furthest, turned for an unwind point.
  core::Status first(const Where& where) {
    const ProgramPoint& pt = points_[0];
    auto pose = machine::inverse(m_, pt.tip_part_mm, pt.tool_axis_part, nullptr);
    if (!pose) return fail(pose.error(), where);
    std::vector<MachinePose> candidates{pose.value()};
    MachinePose hint = pose.value();
    hint.a_or_b_deg = -hint.a_or_b_deg;
    hint.c_deg += hint.c_deg > 0.0 ? -180.0 : 180.0;
    if (auto other = machine::inverse(m_, pt.tip_part_mm, pt.tool_axis_part, &hint)) candidates.push_back(other.value());
    prev_ = pick_branch(m_, points_, 1, candidates);
    if (pt.c_unwind && machine::unwinds_c(m_) && singular(prev_)) {
      auto target = unwind_target_deg(m_, points_, 1, prev_);
      if (!target) return fail(target.error(), where);
      MachinePose at_target = prev_;
      at_target.c_deg = target.value();
      auto turned = machine::inverse(m_, pt.tip_part_mm, pt.tool_axis_part, &at_target);
      if (!turned) return fail(turned.error(), where);
      prev_ = turned.value();
    }
    return w_.move(prev_, /*rapid=*/true, 0.0, where);
  }

  // Leaving the singular axis with the process off, the branch is free: the search's choice.
  core::Status leave_pole(std::size_t i, const Where& where) {
    if (process_on_ || !singular(prev_) || points_[i - 1].c_unwind) return {};
    const auto other = other_branch_at_pole(m_, prev_);
    if (!other) return {};
    const MachinePose chosen = pick_branch(m_, points_, i, {prev_, *other});
    if (chosen.c_deg == prev_.c_deg) return {};
    auto turn = machine::turn_c_in_place(m_, prev_, chosen.c_deg, tol_);
    if (!turn) return fail(turn.error(), where);
    return emit(turn.value(), o_.rapid_travel, p_.travel_feed_mm_s, where);
  }

  // The move from point I − 1 to point I.
  core::Status move_to(std::size_t i, const Where& where) {
    const ProgramPoint& from = points_[i - 1];
    const ProgramPoint& pt = points_[i];
    auto poses = machine::subdivide(m_, from.tip_part_mm, from.tool_axis_part, pt.tip_part_mm, pt.tool_axis_part, prev_, tol_);
    if (!poses) {
      return make_error(poses.error().code, fmt::format("{} from axis ({:.4f}, {:.4f}, {:.4f}) at ({:.4f}, {:.4f}, {:.4f}): {}", where.str(),
                                                        from.tool_axis_part.x, from.tool_axis_part.y, from.tool_axis_part.z, from.tip_part_mm.x,
                                                        from.tip_part_mm.y, from.tip_part_mm.z, end_stop_or(m_, prev_, pt, poses.error().message)));
    }
    if (o_.split_stalls && pt.process_on && stalls(m_, prev_, poses.value(), pt.feed_mm_s) && singular(prev_) && !poses.value().empty()) {
      // Leaving the pole, C swings to the move's own: turn C alone in place with the process off
      // (the tool stays along C, so the tip and the axis hold), then tilt along the bead as planned.
      auto turn = machine::turn_c_in_place(m_, prev_, poses.value().back().c_deg, tol_);
      if (turn && !turn.value().empty()) {
        const MachinePose at_pole = turn.value().back();
        auto along = machine::subdivide(m_, from.tip_part_mm, from.tool_axis_part, pt.tip_part_mm, pt.tool_axis_part, at_pole, tol_);
        if (along && !stalls(m_, at_pole, along.value(), pt.feed_mm_s)) {
          ++stall_splits_, ++pole_splits_;
          switch_process(false);
          if (auto st = emit(turn.value(), o_.rapid_travel, p_.travel_feed_mm_s, where); !st) return st;
          poses = std::move(along);
        }
      }
    }
    if (o_.split_stalls && pt.process_on && stalls(m_, prev_, poses.value(), pt.feed_mm_s)) {
      // The rotary axes cannot keep up with the tip here: turn the tool in place with the process
      // off, then lay the bead with the new axis (verify/verify.h, stall).
      ++stall_splits_;
      auto turn = machine::subdivide(m_, from.tip_part_mm, from.tool_axis_part, from.tip_part_mm, pt.tool_axis_part, prev_, tol_);
      if (!turn) return fail(turn.error(), where);
      switch_process(false);
      if (auto st = emit(turn.value(), o_.rapid_travel, p_.travel_feed_mm_s, where); !st) return st;
      poses = machine::subdivide(m_, from.tip_part_mm, pt.tool_axis_part, pt.tip_part_mm, pt.tool_axis_part, prev_, tol_);
      if (!poses) return fail(poses.error(), where);
    }
    switch_process(pt.process_on);
    return emit(poses.value(), o_.rapid_travel && !pt.process_on, pt.feed_mm_s, where);
  }

  // At an unwind point, C turned by whole (or half) turns to where the coming sweep fits.
  core::Status unwind(std::size_t i, const Where& where) {
    const ProgramPoint& pt = points_[i];
    if (!pt.c_unwind || pt.process_on || !machine::unwinds_c(m_)) return {};
    auto target = unwind_target_deg(m_, points_, i + 1, prev_);
    if (!target) return fail(target.error(), where);
    auto turn = machine::turn_c_in_place(m_, prev_, target.value(), tol_);
    if (!turn) return make_error(turn.error().code, fmt::format("{}: unwinding C: {}", where.str(), turn.error().message));
    if (!turn.value().empty()) ++unwinds_;
    return emit(turn.value(), o_.rapid_travel, p_.travel_feed_mm_s, where);
  }

  std::uint64_t stall_splits() const { return stall_splits_; }
  std::uint64_t pole_splits() const { return pole_splits_; }

  // Switches the process off, and the closing comments.
  void finish() {
    switch_process(false);
    if (stall_splits_ > 0) {
      w_.line(fmt::format("(polyaxis: {} turns in place with the process off, where the rotary axes could not keep the deposit feed)",
                          stall_splits_));
    }
    if (unwinds_ > 0) w_.line(fmt::format("(polyaxis: C unwound {} times, by whole turns with the tool along C)", unwinds_));
    w_.line("M2");
  }

 private:
  core::Error fail(const core::Error& e, const Where& where) const { return make_error(e.code, fmt::format("{}: {}", where.str(), e.message)); }

  core::Status emit(const std::vector<MachinePose>& poses, bool rapid, double feed_mm_s, const Where& where) {
    for (const MachinePose& pose : poses) {
      if (auto st = w_.move(pose, rapid, feed_mm_s, where); !st) return st;
    }
    if (!poses.empty()) prev_ = poses.back();
    return {};
  }

  void switch_process(bool on) {
    if (on == process_on_) return;
    w_.line(on ? p_.process_on : p_.process_off);
    if (on && p_.dwell_on_s > 0.0) w_.line(fmt::format("G4 P{:.4f}", p_.dwell_on_s));
    process_on_ = on;
  }

  const machine::MachineConfig& m_;
  const process::ProcessConfig& p_;
  std::span<const ProgramPoint> points_;
  const GcodeOptions& o_;
  Writer w_;
  // The written words are rounded (0.1 µm, 0.0001°): keep that share of the tolerance in hand so
  // the tip read back from the file stays within options.chordal_mm.
  const double tol_;
  MachinePose prev_{};
  bool process_on_ = false;
  std::uint64_t stall_splits_ = 0, pole_splits_ = 0, unwinds_ = 0;
};

}  // namespace

core::Result<std::string> write_gcode(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                      std::span<const ProgramPoint> points, const GcodeOptions& options) {
  if (points.empty()) return make_error(ErrorCode::kInfeasible, "no program points to write");
  ProgramWriter pw(machine, process, points, options);
  Writer& w = pw.out();
  w.line(fmt::format("(polyaxis: machine {} [{}], process {})", sanitize_comment(machine.name),
                     machine::kinematics_name(machine.kind), sanitize_comment(process.name)));
  w.line("(axis words are joint positions: run with identity kinematics)");
  w.line("G21 G90 G94 G17");
  // Path blending within the machine's tolerance (LinuxCNC's trajectory planner, machine "accel").
  w.line(fmt::format("G64 P{:.4f}", machine.accel.blend_tolerance_mm));
  core::Progress progress("G-code", points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if ((i & 4095) == 0) progress.update(i);
    const ProgramPoint& pt = points[i];
    if (!core::is_finite(pt.tip_part_mm) || !core::is_finite(pt.tool_axis_part) || !std::isfinite(pt.feed_mm_s) ||
        !(norm(pt.tool_axis_part) > 0.0) || !(pt.feed_mm_s > 0.0)) {
      return make_error(ErrorCode::kInternal,
                        fmt::format("{}: a non-finite or zero value (feed {} mm/s)", Where{i, &pt}.str(), pt.feed_mm_s));
    }
    const Where where{i, &pt};
    if (!pt.comment_if_new_block.empty()) {
      w.line(fmt::format("(layer {} region {} {})", pt.layer, pt.region, sanitize_comment(pt.comment_if_new_block)));
    }
    if (i == 0) {
      if (auto st = pw.first(where); !st) return st.error();
      continue;
    }
    if (auto st = pw.leave_pole(i, where); !st) return st.error();
    if (auto st = pw.move_to(i, where); !st) return st.error();
    if (auto st = pw.unwind(i, where); !st) return st.error();
    if (w.over_cap()) {
      return make_error(ErrorCode::kOutput,
                        fmt::format("the program exceeds the output cap of {} bytes at point {}", options.max_output_bytes, i));
    }
  }
  pw.finish();
  if (w.over_cap()) {
    return make_error(ErrorCode::kOutput, fmt::format("the program exceeds the output cap of {} bytes", options.max_output_bytes));
  }
  w.stats_.stall_splits = pw.stall_splits();
  w.stats_.stall_splits_at_pole = pw.pole_splits();
  if (options.stats != nullptr) *options.stats = w.stats_;
  return w.take();
}

core::Status save_gcode(const std::string& path, std::string_view text) {
  return io::write_file_atomic(path, text, io::Durability::kSynced);
}

bool splits_stall(const machine::MachineConfig& m, Vec3 p0, Vec3 t0, Vec3 p1, Vec3 t1, double feed_mm_s, double chordal_mm) {
  auto start = machine::inverse(m, p0, t0, nullptr);
  if (!start) return false;
  MachinePose prev = start.value();
  if (singular(prev)) {
    auto end = machine::inverse(m, p1, t1, &prev);
    if (!end) return false;
    prev.c_deg = end.value().c_deg;  // turned alone at the pole, the axes holding (move_to)
    if (auto at = machine::joints_for_tip(m, p0, prev)) prev = *at;
  }
  auto poses = machine::subdivide(m, p0, t0, p1, t1, prev, chordal_mm * kSubdivisionShare);
  return poses && stalls(m, prev, poses.value(), feed_mm_s);
}

}  // namespace polyaxis::post
