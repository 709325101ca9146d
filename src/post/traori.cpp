#include "polyaxis/post/traori.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "polyaxis/machine/kinematics.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

// A block turning the tool with the tip moving less than this (mm) turns it in place.
constexpr double kStillTipMm = 1e-6;

std::string comment_text(std::string_view s) {
  std::string out;
  for (const char ch : s) out += ch < 0x20 || ch > 0x7e ? '?' : ch;
  return out;
}

// The tip and the unit tool vector as the words write them (4 and 6 decimals).
Vec3 written_tip(Vec3 p) { return {std::round(p.x * 1e4) / 1e4, std::round(p.y * 1e4) / 1e4, std::round(p.z * 1e4) / 1e4}; }
Vec3 written_vector(Vec3 a) {
  a = core::normalized(a);
  return core::normalized(Vec3{std::round(a.x * 1e6) / 1e6, std::round(a.y * 1e6) / 1e6, std::round(a.z * 1e6) / 1e6});
}

// A block slowed to an axis maximum is timed this much longer, for the rounding of its words.
constexpr double kLimitMargin = 1e-5;
// A deposit block whose axes would hold the tip below this share of its feed is split (above
// verify::kStallShare, 0.5, as the LinuxCNC post's kStallGuardShare).
constexpr double kStallGuardShare = 0.6;

std::string where(std::size_t i, const ProgramPoint& p) {
  return fmt::format("move to point {} (layer {} region {}, tip ({:.4f}, {:.4f}, {:.4f}), axis ({:.4f}, {:.4f}, {:.4f}))", i, p.layer, p.region,
                     p.tip_part_mm.x, p.tip_part_mm.y, p.tip_part_mm.z, p.tool_axis_part.x, p.tool_axis_part.y, p.tool_axis_part.z);
}

class TraoriWriter {
 public:
  TraoriWriter(const machine::MachineConfig& m, const process::ProcessConfig& p, const GcodeOptions& o) : m_(m), p_(p), o_(o) {}

  core::Status run(std::span<const ProgramPoint> points) {
    line(fmt::format("; polyaxis: machine {} [{}], process {}, post siemens-traori", comment_text(m_.name), machine::kinematics_name(m_.kind),
                     comment_text(p_.name)));
    line("; TRAORI: X Y Z the tip and A3 B3 C3 the tool vector, workpiece frame; the controller solves the axes");
    line("G17 G90 G71 G94");
    line("TRAORI");
    line("ORIWKS");
    line("ORIVECT");
    for (std::size_t i = 0; i < points.size(); ++i) {
      const ProgramPoint& pt = points[i];
      if (!core::is_finite(pt.tip_part_mm) || !core::is_finite(pt.tool_axis_part) || !(core::norm(pt.tool_axis_part) > 0.0) ||
          !std::isfinite(pt.feed_mm_s) || !(pt.feed_mm_s > 0.0)) {
        return make_error(ErrorCode::kInternal, fmt::format("{}: a non-finite or zero value (feed {} mm/s)", where(i, pt), pt.feed_mm_s));
      }
      // The inverse kinematics of the words as written (what the controller and the read-back see).
      const Vec3 tip = written_tip(pt.tip_part_mm), vec = written_vector(pt.tool_axis_part);
      auto pose = machine::inverse(m_, tip, vec, i == 0 ? nullptr : &prev_);
      if (!pose) return make_error(pose.error().code, fmt::format("{}: {}", where(i, pt), pose.error().message));
      if (!pt.comment_if_new_block.empty()) {
        line(fmt::format("; layer {} region {} {}", pt.layer, pt.region, comment_text(pt.comment_if_new_block)));
      }
      if (i == 0) {
        block("G0", pt, std::nullopt);
      } else {
        const double tip_mm = core::norm(tip - written_tip(points[i - 1].tip_part_mm));
        const bool turns = core::norm(vec - written_vector(points[i - 1].tool_axis_part)) > 0.0;
        if (tip_mm < kStillTipMm && !turns) {
          switch_process(pt.process_on);  // nothing moves: the process state alone
        } else if (tip_mm < kStillTipMm) {
          // The tool turns in place: rapid, with the process off (nothing may be laid on one spot);
          // the next deposit move switches it on again.
          switch_process(false);
          block("G0", pt, std::nullopt);
        } else {
          const double feed = feed_mm_min(tip_mm, pt.feed_mm_s, pose.value());
          if (pt.process_on && turns && feed < kStallGuardShare * 60.0 * pt.feed_mm_s) {
            // The axes would hold the tip below the deposit feed with the process on (the stall
            // verify counts): the tool turns first, in place with the process off, then the bead is
            // laid with the new vector at its feed (as the LinuxCNC post's stall split).
            ProgramPoint turn = pt;
            turn.tip_part_mm = points[i - 1].tip_part_mm;
            auto at_start = machine::inverse(m_, written_tip(turn.tip_part_mm), vec, &prev_);
            if (!at_start) return make_error(at_start.error().code, fmt::format("{}: {}", where(i, pt), at_start.error().message));
            switch_process(false);
            block("G0", turn, std::nullopt);
            prev_ = at_start.value();
            ++stall_splits_;
            switch_process(true);
            block("G1", pt, feed_mm_min(tip_mm, pt.feed_mm_s, pose.value()));
          } else {
            switch_process(pt.process_on);
            block("G1", pt, feed);
          }
        }
      }
      prev_ = pose.value();
      if (o_.max_output_bytes != 0 && out_.size() > o_.max_output_bytes) {
        return make_error(ErrorCode::kOutput, fmt::format("the program exceeds {} bytes", o_.max_output_bytes));
      }
    }
    switch_process(false);
    if (stall_splits_ > 0) {
      line(fmt::format("; polyaxis: {} turns in place with the process off, where the axes could not keep the deposit feed", stall_splits_));
    }
    line("TRAFOOF");
    line("M30");
    return {};
  }

  std::string take() { return std::move(out_); }

 private:
  void line(std::string_view s) {
    out_ += s;
    out_ += '\n';
  }

  void block(const char* motion, const ProgramPoint& pt, std::optional<double> feed) {
    const Vec3 a = core::normalized(pt.tool_axis_part);
    std::string b = fmt::format("{} X{:.4f} Y{:.4f} Z{:.4f} A3={:.6f} B3={:.6f} C3={:.6f}", motion, pt.tip_part_mm.x, pt.tip_part_mm.y,
                                pt.tip_part_mm.z, a.x, a.y, a.z);
    if (feed && (!last_feed_ || *feed != *last_feed_)) {
      b += fmt::format(" F{:.1f}", *feed);
      last_feed_ = feed;
    }
    if (o_.stats != nullptr && std::string_view(motion) == "G1") ++o_.stats->feed_blocks;
    line(b);
  }

  // The tip's path feed (mm/min, one decimal, rounded down) for a block of TIP_MM at the planned
  // FEED_MM_S, slowed until the axes (solved at both ends) stay within the machine's maxima.
  double feed_mm_min(double tip_mm, double feed_mm_s, const MachinePose& to) {
    const double joints_mm = std::hypot(to.x_mm - prev_.x_mm, to.y_mm - prev_.y_mm, to.z_mm - prev_.z_mm);
    const double turn_deg = std::max(std::abs(to.a_or_b_deg - prev_.a_or_b_deg), std::abs(to.c_deg - prev_.c_deg));
    double minutes = tip_mm / (60.0 * feed_mm_s);
    const double linear = joints_mm / m_.feed.linear_max_mm_min, rotary = turn_deg / m_.feed.rotary_max_deg_min;
    if (linear > minutes || rotary > minutes) {
      minutes = std::max(linear, rotary) * (1.0 + kLimitMargin);
      if (o_.stats != nullptr) ++(linear >= rotary ? o_.stats->linear_limited : o_.stats->rotary_limited);
    }
    return std::max(0.1, std::floor(10.0 * tip_mm / minutes) / 10.0);
  }

  void switch_process(bool on) {
    if (on == on_) return;
    line(on ? p_.process_on : p_.process_off);
    if (on && p_.dwell_on_s > 0.0) line(fmt::format("G4 F{:.4f}", p_.dwell_on_s));
    on_ = on;
  }

  const machine::MachineConfig& m_;
  const process::ProcessConfig& p_;
  const GcodeOptions& o_;
  std::string out_;
  MachinePose prev_{};
  bool on_ = false;
  std::optional<double> last_feed_;
  std::uint64_t stall_splits_ = 0;
};

}  // namespace

core::Result<std::string> write_traori(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                       std::span<const ProgramPoint> points, const GcodeOptions& options) {
  if (points.empty()) return make_error(ErrorCode::kInfeasible, "no program points to write");
  if (!machine::has_rotary_axes(machine.kind)) {
    return make_error(ErrorCode::kUsage, fmt::format("TRAORI needs a 5-axis machine; '{}' is {}", machine.name, machine::kinematics_name(machine.kind)));
  }
  TraoriWriter w(machine, process, options);
  if (auto st = w.run(points); !st) return st.error();
  return w.take();
}

core::Result<std::string> write_program(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        std::span<const ProgramPoint> points, const GcodeOptions& options) {
  if (machine.post == machine::PostDialect::kSiemensTraori) return write_traori(machine, process, points, options);
  return write_gcode(machine, process, points, options);
}

std::string_view program_extension(const machine::MachineConfig& machine) {
  return machine.post == machine::PostDialect::kSiemensTraori ? ".mpf" : ".ngc";
}

}  // namespace polyaxis::post
