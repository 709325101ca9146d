#include "polyaxis/post/rapid.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/robot.h"
#include "post/tool_space.h"

namespace polyaxis::post {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

// Rounded to 1/SCALE, never −0 (RAPID reads it, but the text should not show it).
double round_to(double v, double scale) { return std::round(v * scale) / scale + 0.0; }

// The move not yet written: a process switch may still make it end exactly (fine) or turn it into
// the arc's start or end.
struct Motion {
  std::string instr;   // MoveJ, MoveL, ArcLStart, ArcL, ArcLEnd
  std::string target;  // the robtarget
  std::string speed;   // the speeddata
  bool fine = false;
};

class Rapid final : public detail::ToolSpaceDialect {
 public:
  Rapid(const machine::MachineConfig& m, const process::ProcessConfig& p, const GcodeOptions& o) : m_(m), r_(*m.robot), p_(p), o_(o) {}

  core::Result<MachinePose> pose_of(const ProgramPoint& pt, const MachinePose* previous) override {
    auto pose = machine::inverse(m_, detail::written_tip(pt.tip_part_mm), detail::written_vector(pt.tool_axis_part), previous);
    if (!pose) return pose.error();
    // The positioner's angles as written, and the tip's place in the positioner's frame for them:
    // what the reader takes.
    MachinePose p = pose.value();
    p.a_or_b_deg = round_to(p.a_or_b_deg, 1e4);
    p.c_deg = round_to(p.c_deg, 1e4);
    return machine::positioner_pose_for(m_, p, detail::written_tip(pt.tip_part_mm));
  }

  void header() override {
    line("MODULE polyaxis_plan");
    line(fmt::format("  ! polyaxis: machine {} [{} positioner {}], robot {}, process {}, post abb-rapid", text(m_.name),
                     machine::kinematics_name(m_.kind), r_.positioner_unit, text(r_.model), text(p_.name)));
    line("  ! robtargets: the TCP in the part frame on the positioner (mm, quaternion); eax_a, eax_b: the positioner's");
    line(fmt::format("  ! {} and C (degrees); v_tcp: the tip's speed over the part (mm/s)", machine::tilt_axis_letter(m_.kind)));
    line(fmt::format("  PERS tooldata {} := [TRUE,[[{:.4f},{:.4f},{:.4f}],[{:.6f},{:.6f},{:.6f},{:.6f}]],[{:.3f},[0,0,{:.4f}],[1,0,0,0],0,0,0]];",
                     kRapidTool, r_.tcp_mm[0], r_.tcp_mm[1], r_.tcp_mm[2], r_.tcp_quaternion[0], r_.tcp_quaternion[1],
                     r_.tcp_quaternion[2], r_.tcp_quaternion[3], r_.tool_mass_kg, 0.5 * r_.tcp_mm[2]));
    line(fmt::format("  PERS wobjdata {} := [FALSE,FALSE,\"{}\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];", kRapidWobj, r_.positioner_unit));
    line("  PROC main()");
    line("    ConfJ \\On;");
    line("    ConfL \\Off;");
    line("    SingArea \\Wrist;");
    line(fmt::format("    ActUnit {};", r_.positioner_unit));
  }

  // Kept until the move it names: the move before it may still be turned into the arc's end or
  // made to stop exactly by a process switch.
  void comment(const ProgramPoint& pt) override {
    comment_ = fmt::format("    ! layer {} region {} {}", pt.layer, pt.region, detail::comment_text(pt.comment_if_new_block));
  }

  core::Status block(detail::BlockKind kind, const ProgramPoint& pt, const MachinePose& pose, double feed_mm_s, const ProgramPoint*) override {
    Vec3 tip = detail::written_tip(pt.tip_part_mm);
    tip = {tip.x + 0.0, tip.y + 0.0, tip.z + 0.0};
    const machine::Frame3 tcp_world = machine::tcp_world_for(m_, pose, tip, detail::written_vector(pt.tool_axis_part));
    machine::Frame3 in_part = machine::tcp_in_part(m_, pose, tcp_world);
    machine::Quaternion q = machine::quaternion_of(in_part);
    q = {round_to(q.w, 1e6), round_to(q.x, 1e6), round_to(q.y, 1e6), round_to(q.z, 1e6)};
    // The arm is solved for the target as written (what the controller solves).
    const machine::Frame3 written = machine::tcp_in_world(m_, pose, machine::frame_of(tip, q));
    auto chosen = solve(kind, pt, written);
    if (!chosen) return chosen.error();
    const machine::RobotSolution& s = chosen.value();
    const std::string target = fmt::format("[[{:.4f},{:.4f},{:.4f}],[{:.6f},{:.6f},{:.6f},{:.6f}],[{},{},{},{}],[{:.4f},{:.4f},9E+09,9E+09,9E+09,9E+09]]",
                                           tip.x, tip.y, tip.z, q.w, q.x, q.y, q.z, s.conf.cf1, s.conf.cf4, s.conf.cf6, s.conf.cfx,
                                           pose.a_or_b_deg + 0.0, pose.c_deg + 0.0);
    const bool deposit = kind == detail::BlockKind::kFeed && pt.process_on;
    const double v = kind == detail::BlockKind::kFeed ? std::floor(feed_mm_s * 1e3) / 1e3 : p_.travel_feed_mm_s;
    const bool joint_move = kind == detail::BlockKind::kFirst || config_change_;
    const auto [v_ori, v_reax] = turn_speeds(kind, pose, tip, pt.tool_axis_part);
    const std::string speed = fmt::format("[{:.3f},{:.3f},{:.3f},{:.3f}]", std::max(v, 0.001), v_ori, m_.feed.linear_max_mm_min / 60.0, v_reax);
    prev_pose_ = pose, prev_axis_ = core::normalized(pt.tool_axis_part);
    std::string instr = joint_move ? "MoveJ" : deposit && p_.rapid.arc ? "ArcL" : "MoveL";
    flush();
    if (!comment_.empty()) line(comment_), comment_.clear();
    pending_ = Motion{instr, target, speed, joint_move};
    if (o_.stats != nullptr && kind == detail::BlockKind::kFeed) ++o_.stats->feed_blocks;
    return {};
  }

  void switch_process(bool on) override {
    if (on == on_) return;
    on_ = on;
    if (pending_) pending_->fine = true;  // the switch happens at the point, not in a corner zone
    if (p_.rapid.arc) {
      // The arc starts where the move before it ends (ArcLStart) and ends where the last weld
      // move ends (ArcLEnd); a start with no weld move after it is a plain move again.
      if (pending_ && on && pending_->instr == "MoveL") pending_->instr = "ArcLStart";
      if (pending_ && !on && pending_->instr == "ArcL") pending_->instr = "ArcLEnd";
      if (pending_ && !on && pending_->instr == "ArcLStart") pending_->instr = "MoveL";
      return;
    }
    line(fmt::format("    SetDO {},{};", p_.rapid.signal, on ? 1 : 0));
    if (on && p_.dwell_on_s > 0.0) line(fmt::format("    WaitTime {:.3f};", p_.dwell_on_s));
  }

  void footer(std::uint64_t stall_splits) override {
    if (pending_) pending_->fine = true;
    flush();
    if (stall_splits > 0) {
      line(fmt::format("    ! polyaxis: {} turns in place with the process off, where the axes could not keep the deposit feed", stall_splits));
    }
    line(fmt::format("    DeactUnit {};", r_.positioner_unit));
    line("  ENDPROC");
    line("ENDMODULE");
  }

  std::size_t size() const override { return out_.size(); }
  std::string take() { return std::move(out_); }

 private:
  // v_ori and v_reax (°/s, rounded down to 0.001): the rotary maximum, lowered on a move that only
  // turns (a turn in place, a joint move) until the TCP, which the turning part carries round,
  // stays within the linear maximum. A feed move's v_tcp is already lowered for it.
  std::pair<double, double> turn_speeds(detail::BlockKind kind, const MachinePose& to, Vec3, Vec3 axis) const {
    const double rot = m_.feed.rotary_max_deg_min / 60.0, lin = m_.feed.linear_max_mm_min / 60.0;
    if (kind == detail::BlockKind::kFeed || kind == detail::BlockKind::kFirst) return {rot, rot};
    const double l_mm = std::hypot(to.x_mm - prev_pose_.x_mm, to.y_mm - prev_pose_.y_mm, to.z_mm - prev_pose_.z_mm);
    const double reax_deg = std::max(std::abs(to.a_or_b_deg - prev_pose_.a_or_b_deg), std::abs(to.c_deg - prev_pose_.c_deg));
    const Vec3 a = core::normalized(axis);
    const double ori_deg = std::atan2(core::norm(core::cross(prev_axis_, a)), core::dot(prev_axis_, a)) * 180.0 / M_PI;
    const double t = std::max({reax_deg / rot, ori_deg / rot, l_mm / lin}) * (1.0 + 1e-5);
    if (!(t > 0.0)) return {rot, rot};
    auto down = [](double v) { return std::max(0.001, std::floor(v * 1e3) / 1e3); };
    return {down(std::min(rot, ori_deg / t)), down(std::min(rot, reax_deg / t))};
  }

  static std::string text(std::string_view s) {
    std::string t = detail::comment_text(s);
    std::replace(t.begin(), t.end(), '"', '\'');
    return t;
  }

  void line(std::string_view s) {
    flush();
    out_ += s;
    out_ += '\n';
  }

  void flush() {
    if (!pending_) return;
    const Motion& mv = *pending_;
    const bool arc = mv.instr.rfind("Arc", 0) == 0;
    out_ += fmt::format("    {} {},{},{}{},{}\\WObj:={};\n", mv.instr, mv.target, mv.speed,
                        arc ? fmt::format("{},{},", p_.rapid.seam, p_.rapid.weld) : std::string(), mv.fine ? "fine" : "z0", kRapidTool,
                        kRapidWobj);
    pending_.reset();
  }

  // The arm's joints for WORLD: the solution nearest the last one in the same configuration; a new
  // configuration only where the process is off (a joint move); every statistic on the way.
  core::Result<machine::RobotSolution> solve(detail::BlockKind kind, const ProgramPoint& pt, const machine::Frame3& world) {
    const auto sols = machine::robot_solutions(r_, world, have_q_ ? &q_ : nullptr);
    if (sols.empty()) return make_error(ErrorCode::kMachineLimit, fmt::format("the robot cannot reach it: {}", machine::robot_unreachable_reason(r_, world)));
    const machine::RobotJoints home{};
    const machine::RobotJoints& from = have_q_ ? q_ : home;
    auto step = [&](const machine::RobotSolution& s) {
      double d = 0.0;
      for (std::size_t k = 0; k < 6; ++k) d = std::max(d, std::abs(s.q[k] - from[k]));
      return d;
    };
    const machine::RobotSolution* best = nullptr;
    for (const auto& s : sols) {
      const bool same = !have_q_ || s.conf.cfx == conf_.cfx;
      const bool best_same = best != nullptr && (!have_q_ || best->conf.cfx == conf_.cfx);
      if (best == nullptr || (same && !best_same) || (same == best_same && step(s) < step(*best))) best = &s;
    }
    config_change_ = have_q_ && best->conf.cfx != conf_.cfx;
    if (config_change_ && kind == detail::BlockKind::kFeed && pt.process_on) {
      return make_error(ErrorCode::kMachineLimit,
                        fmt::format("the robot must change its configuration (cfx {} to {}) inside a bead", conf_.cfx, best->conf.cfx));
    }
    if (post::GcodeStats* st = o_.stats) {
      ++st->robot_targets;
      st->robot_config_changes += config_change_ ? 1 : 0;
      st->robot_near_singular += best->wrist_deg < r_.wrist_margin_deg ? 1 : 0;
      st->robot_min_wrist_deg = std::min(st->robot_min_wrist_deg, best->wrist_deg);
      for (std::size_t k = 0; k < 6; ++k) {
        st->robot_min_joint_margin_deg = std::min({st->robot_min_joint_margin_deg, best->q[k] - r_.min_deg[k], r_.max_deg[k] - best->q[k]});
      }
      if (have_q_ && !config_change_) st->robot_max_joint_step_deg = std::max(st->robot_max_joint_step_deg, step(*best));
    }
    q_ = best->q, conf_ = best->conf, have_q_ = true;
    return *best;
  }

  const machine::MachineConfig& m_;
  const machine::RobotCell& r_;
  const process::ProcessConfig& p_;
  const GcodeOptions& o_;
  std::string out_;
  std::optional<Motion> pending_;
  std::string comment_;
  MachinePose prev_pose_{};
  Vec3 prev_axis_{0.0, 0.0, 1.0};
  bool on_ = false;
  machine::RobotJoints q_{};
  machine::RobotConfiguration conf_;
  bool have_q_ = false, config_change_ = false;
};

}  // namespace

core::Result<std::string> write_rapid(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                      std::span<const ProgramPoint> points, const GcodeOptions& options) {
  if (points.empty()) return make_error(ErrorCode::kInfeasible, "no program points to write");
  if (!machine.robot || !machine::turns_table(machine.kind)) {
    return make_error(ErrorCode::kUsage, fmt::format("a RAPID program needs a robot over a positioner; '{}' has none", machine.name));
  }
  Rapid w(machine, process, options);
  if (auto st = detail::write_tool_space(machine, points, options, w); !st) return st.error();
  return w.take();
}

}  // namespace polyaxis::post
