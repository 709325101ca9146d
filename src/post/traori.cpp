#include "polyaxis/post/traori.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "polyaxis/machine/kinematics.h"
#include "polyaxis/post/rapid.h"
#include "post/tool_space.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

class Traori final : public detail::GcodeDialect {
 public:
  using GcodeDialect::GcodeDialect;

  core::Result<MachinePose> pose_of(const ProgramPoint& pt, const MachinePose* previous) override {
    // The inverse kinematics of the words as written (what the controller and the read-back see).
    return machine::inverse(m_, detail::written_tip(pt.tip_part_mm), detail::written_vector(pt.tool_axis_part), previous);
  }

  void header() override {
    line(fmt::format("; polyaxis: machine {} [{}], process {}, post siemens-traori", detail::comment_text(m_.name),
                     machine::kinematics_name(m_.kind), detail::comment_text(p_.name)));
    line("; TRAORI: X Y Z the tip and A3 B3 C3 the tool vector, workpiece frame; the controller solves the axes");
    line("G17 G90 G71 G94");
    line("TRAORI");
    line("ORIWKS");
    line("ORIVECT");
  }

  void comment(const ProgramPoint& pt) override {
    line(fmt::format("; layer {} region {} {}", pt.layer, pt.region, detail::comment_text(pt.comment_if_new_block)));
  }

  core::Status block(detail::BlockKind kind, const ProgramPoint& pt, const MachinePose&, double feed_mm_s, const ProgramPoint*) override {
    const bool feed = kind == detail::BlockKind::kFeed;
    // The words are the very values the loop timed and pose_of solved (detail::written_tip and
    // the vector rounded to 6 decimals): printing the raw values would round half-way cases
    // otherwise, and a 0.1 µm difference on a short block moves its axes' speed past a maximum.
    const Vec3 t = detail::written_tip(pt.tip_part_mm), a = detail::rounded_vector(pt.tool_axis_part);
    std::string b = fmt::format("{} X{:.4f} Y{:.4f} Z{:.4f} A3={:.6f} B3={:.6f} C3={:.6f}", feed ? "G1" : "G0", t.x, t.y, t.z, a.x, a.y, a.z);
    if (feed) b += feed_word(feed_mm_s);
    line(b);
    return {};
  }

  void footer(std::uint64_t stall_splits) override {
    if (stall_splits > 0) {
      line(fmt::format("; polyaxis: {} turns in place with the process off, where the axes could not keep the deposit feed", stall_splits));
    }
    line("TRAFOOF");
    line("M30");
  }

 private:
  std::string dwell_block(double seconds) const override { return fmt::format("G4 F{:.4f}", seconds); }  // F: seconds
};

}  // namespace

core::Result<std::string> write_traori(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                       std::span<const ProgramPoint> points, const GcodeOptions& options) {
  Traori w(machine, process, options);
  return detail::write_oriented("TRAORI", machine, points, options, w);
}

}  // namespace polyaxis::post
