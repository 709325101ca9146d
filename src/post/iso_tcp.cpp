#include "polyaxis/post/iso_tcp.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <vector>

#include "polyaxis/machine/kinematics.h"
#include "post/tool_space.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using core::make_error;
using machine::MachinePose;

// A rotary word as written (4 decimals).
double written_deg(double v) { return std::round(v * 1e4) / 1e4; }

// The largest angle (degrees) between the tool axis the controller gives inside a block (the
// rotary axes turned linearly) and the plan's (the great circle between the block's ends); a block
// bending further is written in pieces along the great circle.
constexpr double kAxisChordDeg = 0.05;
// At most this many pieces to a block (a half turn of C at 0.05° needs about 60).
constexpr int kMaxPieces = 1024;
// A bead's pieces slowed below this share of its planned feed would stall (verify counts below
// 0.5; the tool-space loop's guard is 0.6).
constexpr double kStallShare = 0.6;
// A piece slowed to an axis maximum is timed this much longer, for the rounding of its words (as
// the tool-space loop's blocks).
constexpr double kLimitMargin = 1e-5;

double angle_deg(core::Vec3 a, core::Vec3 b) { return std::atan2(core::norm(core::cross(a, b)), core::dot(a, b)) * 180.0 / M_PI; }

// The great circle from unit A to unit B at U.
core::Vec3 great_circle(core::Vec3 a, core::Vec3 b, double u) {
  const double w = std::atan2(core::norm(core::cross(a, b)), core::dot(a, b));
  if (!(std::sin(w) > 1e-12)) return core::normalized(a * (1.0 - u) + b * u);
  return core::normalized(a * (std::sin((1.0 - u) * w) / std::sin(w)) + b * (std::sin(u * w) / std::sin(w)));
}

class IsoTcp final : public detail::GcodeDialect {
 public:
  using GcodeDialect::GcodeDialect;

  core::Result<MachinePose> pose_of(const ProgramPoint& pt, const MachinePose* previous) override {
    return pose_at(detail::written_tip(pt.tip_part_mm), detail::written_vector(pt.tool_axis_part), previous);
  }

  // The axes as the controller will put them for TIP and AXIS: the rotary words as written, and
  // the linear axes that bring the written tip there (so that feeds are timed on what the machine does).
  core::Result<MachinePose> pose_at(core::Vec3 tip, core::Vec3 axis, const MachinePose* previous) const {
    auto pose = machine::inverse(m_, tip, axis, previous);
    if (!pose) return pose;
    pose.value().a_or_b_deg = written_deg(pose.value().a_or_b_deg), pose.value().c_deg = written_deg(pose.value().c_deg);
    const auto joints = machine::joints_for_tip(m_, tip, pose.value());
    if (!joints) return make_error(ErrorCode::kInternal, "no linear axis pose puts the tip there");
    if (const std::string why = machine::limit_violation(m_, *joints); !why.empty()) return make_error(ErrorCode::kMachineLimit, why);
    return *joints;
  }

  void header() override {
    line("%");
    line(fmt::format("(polyaxis: machine {} [{}], process {}, post iso-tcp)", text(m_.name), machine::kinematics_name(m_.kind), text(p_.name)));
    line(fmt::format("(X Y Z: the tip in the workpiece frame, {} C: the rotary axes; G43.4: the controller keeps the tip)", tilt_));
    line("G21 G90 G94 G17");
    line("G43.4 H1");
  }

  void comment(const ProgramPoint& pt) override { line(fmt::format("(layer {} region {} {})", pt.layer, pt.region, text(pt.comment_if_new_block))); }

  core::Status block(detail::BlockKind kind, const ProgramPoint& pt, const MachinePose& pose, double feed_mm_s, const ProgramPoint*) override {
    const core::Vec3 tip = detail::written_tip(pt.tip_part_mm), axis = detail::written_vector(pt.tool_axis_part);
    struct Piece {
      core::Vec3 tip;
      MachinePose pose;
      double feed_mm_s;
    };
    std::vector<Piece> pieces{{tip, pose, feed_mm_s}};
    for (int n = kind == detail::BlockKind::kFirst ? 1 : count_pieces(last_, pose, last_axis_, axis_of(pose)); n > 1;) {
      // The tip and the great circle's axis at k/n, as the controller will put them, each piece
      // slowed to its own axes' maxima; twice as many pieces while one still bends too far. A bead
      // whose pieces would stall (below kStallShare of its planned feed, where the axes turn fast
      // near the tilt's singularity) turns in place first (turn_then_bead).
      std::vector<Piece> split;
      MachinePose from = last_;
      core::Vec3 from_tip = last_tip_, from_axis = last_axis_;
      bool stalls = false, bends = false;
      for (int k = 1; k <= n; ++k) {
        const double u = static_cast<double>(k) / n;
        Piece p{tip, pose, feed_mm_s};
        if (k < n) {
          p.tip = detail::written_tip(last_tip_ + (tip - last_tip_) * u);
          auto at = pose_at(p.tip, great_circle(last_axis_, axis, u), &from);
          if (!at) return at.error();
          p.pose = at.value();
        }
        if (kind == detail::BlockKind::kFeed) p.feed_mm_s = piece_feed(from_tip, p.tip, from, p.pose, feed_mm_s);
        stalls = stalls || (pt.process_on && p.feed_mm_s < kStallShare * pt.feed_mm_s);
        const core::Vec3 to_axis = great_circle(last_axis_, axis, u);
        bends = bends || count_pieces(from, p.pose, from_axis, to_axis) > 1;
        split.push_back(p);
        from = p.pose, from_tip = p.tip, from_axis = to_axis;
      }
      if (stalls) return turn_then_bead(pt, pose, tip, axis, feed_mm_s);
      pieces = std::move(split);
      if (!bends || n >= kMaxPieces) break;
      n = std::min(kMaxPieces, 2 * n);
    }
    for (const Piece& p : pieces) write(kind, p.tip, p.pose, p.feed_mm_s);
    last_ = pose, last_tip_ = tip, last_axis_ = axis;
    return {};
  }

  // A bead whose axes would stall it along the great circle (near the tilt's singularity): as the
  // tool-space loop's stall split, the tool turns first where it stands, with the process off and
  // in pieces along the great circle, then the bead is laid with the new axis at its feed.
  core::Status turn_then_bead(const ProgramPoint& pt, const MachinePose& pose, core::Vec3 tip, core::Vec3 axis, double feed_mm_s) {
    auto start = pose_at(last_tip_, axis, &last_);
    if (!start) return start.error();
    switch_process(false);
    MachinePose from = last_;
    const int n = std::max(1, count_pieces(last_, start.value(), last_axis_, axis));
    for (int k = 1; k <= n; ++k) {
      auto at = k == n ? start : pose_at(last_tip_, great_circle(last_axis_, axis, static_cast<double>(k) / n), &from);
      if (!at) return at.error();
      write(detail::BlockKind::kTurnInPlace, last_tip_, at.value(), 0.0);
      from = at.value();
    }
    switch_process(pt.process_on);
    write(detail::BlockKind::kFeed, tip, pose, piece_feed(last_tip_, tip, start.value(), pose, feed_mm_s));
    last_ = pose, last_tip_ = tip, last_axis_ = axis;
    return {};
  }

  void footer(std::uint64_t stall_splits) override {
    if (stall_splits > 0) line(fmt::format("(polyaxis: {} turns in place with the process off, where the axes could not keep the deposit feed)", stall_splits));
    line("G49");
    line("M30");
    line("%");
  }

 private:
  core::Result<MachinePose> pose_at(core::Vec3 tip, core::Vec3 axis, const MachinePose& previous) const { return pose_at(tip, axis, &previous); }

  // How many pieces keep the axis of the move from FROM (axis FROM_AXIS) to TO (TO_AXIS) within
  // kAxisChordDeg of the great circle between them (the deviation shrinks with the square of the
  // piece's turn); 1 when it already does.
  int count_pieces(const MachinePose& from, const MachinePose& to, core::Vec3 from_axis, core::Vec3 to_axis) const {
    double worst = 0.0;
    for (const double u : {0.25, 0.5, 0.75}) {
      MachinePose mid = from;
      mid.a_or_b_deg += (to.a_or_b_deg - from.a_or_b_deg) * u;
      mid.c_deg += (to.c_deg - from.c_deg) * u;
      worst = std::max(worst, angle_deg(axis_of(mid), great_circle(from_axis, to_axis, u)));
    }
    if (worst <= kAxisChordDeg) return 1;
    return std::min(kMaxPieces, static_cast<int>(std::ceil(std::sqrt(worst / kAxisChordDeg) * 1.25)));
  }

  core::Vec3 axis_of(MachinePose p) const {
    p.x_mm = p.y_mm = p.z_mm = 0.0;
    return core::normalized(machine::forward(m_, p).tool_axis_part);
  }

  // A piece's feed (mm/s) from FROM_TIP and FROM to TIP and TO: the block's FEED_MM_S, slowed where
  // the piece's own axes would pass a maximum.
  double piece_feed(core::Vec3 from_tip, core::Vec3 tip, const MachinePose& from, const MachinePose& to, double feed_mm_s) const {
    const double tip_mm = core::norm(tip - from_tip);
    const double joints_mm = std::hypot(to.x_mm - from.x_mm, to.y_mm - from.y_mm, to.z_mm - from.z_mm);
    const double turn_deg = std::max(std::abs(to.a_or_b_deg - from.a_or_b_deg), std::abs(to.c_deg - from.c_deg));
    const double minutes = std::max(joints_mm / m_.feed.linear_max_mm_min, turn_deg / m_.feed.rotary_max_deg_min) * (1.0 + kLimitMargin);
    if (!(tip_mm > 0.0) || minutes <= 0.0) return feed_mm_s;
    return std::min(feed_mm_s, std::max(0.1, std::floor(10.0 * tip_mm / minutes + 1e-9) / 10.0) / 60.0);
  }

  void write(detail::BlockKind kind, core::Vec3 t, const MachinePose& pose, double feed_mm_s) {
    const bool feed = kind == detail::BlockKind::kFeed;
    std::string b = fmt::format("{} X{:.4f} Y{:.4f} Z{:.4f} {}{:.4f} C{:.4f}", feed ? "G1" : "G0", t.x, t.y, t.z, tilt_, pose.a_or_b_deg, pose.c_deg);
    if (feed) b += feed_word(feed_mm_s);
    line(b);
  }

  std::string dwell_block(double seconds) const override { return fmt::format("G4 X{:.4f}", seconds); }  // X: seconds (Fanuc)
  // Comment text: printable ASCII without parentheses, which would end the comment.
  static std::string text(std::string_view s) {
    std::string out = detail::comment_text(s);
    for (char& c : out) c = (c == '(' || c == ')') ? '?' : c;
    return out;
  }
  const char tilt_ = machine::tilt_axis_letter(m_.kind);
  MachinePose last_{};  // the last block's pose, tip and axis as written
  core::Vec3 last_tip_{}, last_axis_{0, 0, 1};
};

}  // namespace

core::Result<std::string> write_iso_tcp(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        std::span<const ProgramPoint> points, const GcodeOptions& options) {
  IsoTcp w(machine, process, options);
  return detail::write_oriented("ISO TCP (G43.4)", machine, points, options, w);
}

}  // namespace polyaxis::post
