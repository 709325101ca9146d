#include "polyaxis/post/iso_tcp.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "polyaxis/machine/kinematics.h"
#include "post/tool_space.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using core::make_error;
using machine::MachinePose;

// A rotary word as written (4 decimals).
double written_deg(double v) { return std::round(v * 1e4) / 1e4; }

class IsoTcp final : public detail::GcodeDialect {
 public:
  using GcodeDialect::GcodeDialect;

  core::Result<MachinePose> pose_of(const ProgramPoint& pt, const MachinePose* previous) override {
    // The axes as the controller will put them: the rotary words as written, and the linear axes
    // that bring the written tip there (so that feeds are timed on what the machine does).
    const core::Vec3 tip = detail::written_tip(pt.tip_part_mm);
    auto pose = machine::inverse(m_, tip, detail::written_vector(pt.tool_axis_part), previous);
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
    const bool feed = kind == detail::BlockKind::kFeed;
    const core::Vec3 t = detail::written_tip(pt.tip_part_mm);  // the values the loop timed (traori.cpp says why)
    std::string b = fmt::format("{} X{:.4f} Y{:.4f} Z{:.4f} {}{:.4f} C{:.4f}", feed ? "G1" : "G0", t.x, t.y, t.z, tilt_, pose.a_or_b_deg, pose.c_deg);
    if (feed) b += feed_word(feed_mm_s);
    line(b);
    return {};
  }

  void footer(std::uint64_t stall_splits) override {
    if (stall_splits > 0) line(fmt::format("(polyaxis: {} turns in place with the process off, where the axes could not keep the deposit feed)", stall_splits));
    line("G49");
    line("M30");
    line("%");
  }

 private:
  std::string dwell_block(double seconds) const override { return fmt::format("G4 X{:.4f}", seconds); }  // X: seconds (Fanuc)
  // Comment text: printable ASCII without parentheses, which would end the comment.
  static std::string text(std::string_view s) {
    std::string out = detail::comment_text(s);
    for (char& c : out) c = (c == '(' || c == ')') ? '?' : c;
    return out;
  }
  const char tilt_ = machine::tilt_axis_letter(m_.kind);
};

}  // namespace

core::Result<std::string> write_iso_tcp(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        std::span<const ProgramPoint> points, const GcodeOptions& options) {
  IsoTcp w(machine, process, options);
  return detail::write_oriented("ISO TCP (G43.4)", machine, points, options, w);
}

}  // namespace polyaxis::post
