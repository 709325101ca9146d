// Reading an ABB RAPID module (post/rapid.h) for the simulator, the build verifier and the
// playback: the subset polyaxis writes, and named robtargets. Each motion statement becomes a
// WalkMove in tool space (the TCP straight over the part, the tool axis −z turning along the great
// circle: the controller's orientation interpolation for the small turns between targets), or,
// for MoveJ, joint-interpolated through the robot's own forward kinematics.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "gcode_walk.h"
#include "polyaxis/machine/robot.h"

namespace polyaxis::verify::detail {
namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

// A value of RAPID's aggregate syntax: a number, a string, a name (TRUE, v100, fine, ...) or a list.
struct Value {
  enum class Kind { kNumber, kString, kName, kList } kind = Kind::kName;
  double number = 0.0;
  std::string text;
  std::vector<Value> items;
};

constexpr double kMaxMagnitude = 1e10;  // 9E+09 marks an absent external axis; anything larger is no value of a cell
constexpr int kMaxDepth = 8;

class Parser {
 public:
  explicit Parser(std::string_view s) : s_(s) {}
  bool value(Value& out, std::string& why, int depth = 0) {
    skip();
    if (i_ >= s_.size()) return fail(why, "a value is missing");
    const char ch = s_[i_];
    if (ch == '[') {
      if (depth >= kMaxDepth) return fail(why, "brackets nested too deeply");
      ++i_;
      out.kind = Value::Kind::kList;
      skip();
      if (i_ < s_.size() && s_[i_] == ']') return ++i_, true;
      while (true) {
        Value v;
        if (!value(v, why, depth + 1)) return false;
        out.items.push_back(std::move(v));
        skip();
        if (i_ < s_.size() && s_[i_] == ',') {
          ++i_;
          continue;
        }
        if (i_ < s_.size() && s_[i_] == ']') return ++i_, true;
        return fail(why, "',' or ']' expected");
      }
    }
    if (ch == '"') {
      const std::size_t close = s_.find('"', i_ + 1);
      if (close == std::string_view::npos) return fail(why, "unclosed string");
      out.kind = Value::Kind::kString;
      out.text = std::string(s_.substr(i_ + 1, close - i_ - 1));
      i_ = close + 1;
      return true;
    }
    if (ch == '-' || ch == '+' || ch == '.' || std::isdigit(static_cast<unsigned char>(ch))) {
      std::size_t j = i_ + 1;
      while (j < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[j])) || s_[j] == '.' || s_[j] == 'E' || s_[j] == 'e' ||
                               ((s_[j] == '+' || s_[j] == '-') && (s_[j - 1] == 'E' || s_[j - 1] == 'e')))) {
        ++j;
      }
      const char* first = s_.data() + i_ + (ch == '+' ? 1 : 0);
      const auto [ptr, ec] = std::from_chars(first, s_.data() + j, out.number);
      if (ec != std::errc() || ptr != s_.data() + j || !std::isfinite(out.number) || std::abs(out.number) > kMaxMagnitude) {
        return fail(why, fmt::format("'{}' is not a number of a cell", s_.substr(i_, j - i_)));
      }
      out.kind = Value::Kind::kNumber;
      i_ = j;
      return true;
    }
    if (std::isalpha(static_cast<unsigned char>(ch)) || ch == '\\') {
      // A name, or an optional argument: \Switch or \Name:=name.
      auto word_end = [&](std::size_t j) {
        while (j < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_')) ++j;
        return j;
      };
      std::size_t j = word_end(i_ + 1);
      if (ch == '\\' && s_.substr(j, 2) == ":=") j = word_end(j + 2);
      out.kind = Value::Kind::kName;
      out.text = std::string(s_.substr(i_, j - i_));
      i_ = j;
      return true;
    }
    return fail(why, fmt::format("unexpected '{}'", ch));
  }
  // The statement's arguments: values separated by commas, switches (\WObj:=name) kept as names.
  bool arguments(std::vector<Value>& out, std::string& why) {
    while (true) {
      skip();
      if (i_ >= s_.size()) return true;
      Value v;
      if (!value(v, why)) return false;
      out.push_back(std::move(v));
      skip();
      if (i_ < s_.size() && s_[i_] == ',') ++i_;
    }
  }

 private:
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  static bool fail(std::string& why, std::string msg) {
    why = std::move(msg);
    return false;
  }
  std::string_view s_;
  std::size_t i_ = 0;
};

// N numbers of a list value, or false.
bool numbers(const Value& v, std::size_t n, double* out) {
  if (v.kind != Value::Kind::kList || v.items.size() != n) return false;
  for (std::size_t k = 0; k < n; ++k) {
    if (v.items[k].kind != Value::Kind::kNumber) return false;
    out[k] = v.items[k].number;
  }
  return true;
}

// A robtarget [[x,y,z],[q1..q4],[cf1,cf4,cf6,cfx],[eax_a..eax_f]].
struct Target {
  Vec3 pos;
  machine::Quaternion rot;
  machine::RobotConfiguration conf;
  double eax_a = 0.0, eax_b = 0.0;
};
bool target_of(const Value& v, Target& t, std::string& why) {
  double p[3], q[4], cf[4], ex[6];
  if (v.kind != Value::Kind::kList || v.items.size() != 4 || !numbers(v.items[0], 3, p) || !numbers(v.items[1], 4, q) ||
      !numbers(v.items[2], 4, cf) || !numbers(v.items[3], 6, ex)) {
    why = "a robtarget is [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,...,eax_f]]";
    return false;
  }
  if (!(std::hypot(q[0], q[1], q[2]) + std::abs(q[3]) > 0.0)) {
    why = "a zero quaternion";
    return false;
  }
  if (std::abs(ex[0]) >= 1e9 || std::abs(ex[1]) >= 1e9) {
    why = "the positioner's axes (eax_a, eax_b) are not given";
    return false;
  }
  t = {{p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]}, {static_cast<int>(cf[0]), static_cast<int>(cf[1]), static_cast<int>(cf[2]), static_cast<int>(cf[3])},
       ex[0], ex[1]};
  return true;
}

// v_tcp, v_ori, v_reax of a speeddata: inline [v_tcp, v_ori, v_leax, v_reax] or a predefined vN.
bool speed_of(const Value& v, double out[3], std::string& why) {
  double s[4];
  if (numbers(v, 4, s)) {
    if (!(s[0] > 0.0 && s[1] > 0.0 && s[3] > 0.0)) return why = "speeds must be > 0", false;
    out[0] = s[0], out[1] = s[1], out[2] = s[3];
    return true;
  }
  if (v.kind == Value::Kind::kName && v.text.size() > 1 && v.text[0] == 'v') {
    double n = 0.0;
    const auto [ptr, ec] = std::from_chars(v.text.data() + 1, v.text.data() + v.text.size(), n);
    if (ec == std::errc() && ptr == v.text.data() + v.text.size() && n > 0.0) {
      out[0] = n, out[1] = 500.0, out[2] = 1000.0;  // ABB's predefined vN: v_ori 500 °/s, v_reax 1000 °/s
      return true;
    }
  }
  why = "a speeddata is [v_tcp,v_ori,v_leax,v_reax] or vN";
  return false;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// "! layer N region R ..." : N and R.
bool layer_comment(std::string_view comment, std::int64_t& layer, std::int64_t& region) {
  long long l = 0, r = 0;
  const std::string c(trim(comment));
  if (std::sscanf(c.c_str(), "layer %lld region %lld", &l, &r) != 2) return false;
  layer = l, region = r;
  return true;
}

class RapidWalk {
 public:
  RapidWalk(const machine::MachineConfig& m, const process::ProcessConfig* p, const WalkCallbacks& cb) : m_(m), r_(*m.robot), p_(p), cb_(cb) {}

  core::Status run(std::string_view text, bool* program_end) {
    std::string statement;
    std::uint64_t line_no = 0, start_line = 0;
    std::size_t at = 0;
    while (at <= text.size() && !end_) {
      const std::size_t nl = text.find('\n', at);
      std::string_view line = text.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
      at = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
      ++line_no;
      if (const std::size_t bang = bang_outside_string(line); bang != std::string_view::npos) {
        if (statement.empty()) layer_comment(line.substr(bang + 1), layer_, region_);
        line = line.substr(0, bang);
      }
      const std::string_view t = trim(line);
      if (t.empty()) continue;
      if (statement.empty()) {
        start_line = line_no;
        if (auto st = block_word(t, line_no); !st) return st;
        if (block_word_seen_) continue;
      }
      statement += ' ';
      statement += t;
      if (statement.size() > 1 << 20) return bad(start_line, "a statement longer than 1 MB", statement.substr(0, 80));
      if (t.back() != ';') continue;
      statement.pop_back();
      if (auto st = execute(trim(statement), start_line); !st) return st;
      statement.clear();
    }
    if (!statement.empty()) return bad(start_line, "the last statement has no ';'", statement.substr(0, 80));
    if (program_end != nullptr) *program_end = end_;
    return {};
  }

 private:
  static std::size_t bang_outside_string(std::string_view line) {
    bool in_string = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '"') in_string = !in_string;
      if (line[i] == '!' && !in_string) return i;
    }
    return std::string_view::npos;
  }

  core::Status bad(std::uint64_t line, const std::string& why, std::string_view text) const {
    return make_error(ErrorCode::kInvalidInput, fmt::format("RAPID line {}: {}: {}", line, why, text));
  }

  // MODULE, PROC, ENDPROC, ENDMODULE stand without ';'.
  core::Status block_word(std::string_view t, std::uint64_t line) {
    block_word_seen_ = true;
    const std::string_view head = t.substr(0, t.find_first_of(" \t("));
    if (head == "MODULE") {
      if (module_) return bad(line, "a second MODULE", t);
      module_ = true;
    } else if (head == "PROC") {
      if (!module_ || in_proc_) return bad(line, "PROC outside a module or inside another", t);
      in_proc_ = true;
    } else if (head == "ENDPROC") {
      if (!in_proc_) return bad(line, "ENDPROC without PROC", t);
      in_proc_ = false;
      end_ = true;  // the module runs its one routine to its end
    } else if (head == "ENDMODULE") {
      module_ = false;
    } else {
      block_word_seen_ = false;
      if (!module_) return bad(line, "a statement outside MODULE ... ENDMODULE", t);
    }
    return {};
  }

  core::Status execute(std::string_view s, std::uint64_t line) {
    const std::size_t sp = s.find_first_of(" \t");
    const std::string_view head = s.substr(0, sp);
    const std::string_view rest = sp == std::string_view::npos ? std::string_view() : s.substr(sp + 1);
    if (head == "PERS" || head == "CONST" || head == "VAR" || head == "TASK") return declaration(s, line);
    if (!in_proc_) return bad(line, "an instruction outside PROC", s);
    std::vector<Value> args;
    std::string why;
    if (!Parser(rest).arguments(args, why)) return bad(line, why, s);
    if (head == "MoveL" || head == "MoveJ" || head == "ArcLStart" || head == "ArcL" || head == "ArcLEnd") return motion(head, args, line, s);
    if (head == "SetDO") {
      if (args.size() != 2 || args[0].kind != Value::Kind::kName || args[1].kind != Value::Kind::kNumber) return bad(line, "SetDO signal, 0 or 1", s);
      if (p_ != nullptr && !p_->rapid.arc && args[0].text == p_->rapid.signal) on_ = args[1].number != 0.0;
      return {};
    }
    if (head == "WaitTime") {
      if (args.empty() || args[0].kind != Value::Kind::kNumber || args[0].number < 0.0) return bad(line, "WaitTime seconds", s);
      if (cb_.dwell) cb_.dwell(line, args[0].number, on_);
      return {};
    }
    if (head == "ConfJ" || head == "ConfL" || head == "SingArea" || head == "ActUnit" || head == "DeactUnit") return {};
    return bad(line, fmt::format("'{}' is not read (polyaxis reads MoveL MoveJ ArcLStart ArcL ArcLEnd SetDO WaitTime ConfJ ConfL SingArea ActUnit DeactUnit)", head), s);
  }

  // "PERS tooldata t := [...]", "CONST robtarget p := [...]": the tool and the work object must be
  // the cell's (the machine file's TCP, a work object on the positioner with identity frames);
  // robtargets are kept by name.
  core::Status declaration(std::string_view s, std::uint64_t line) {
    const std::size_t assign = s.find(":=");
    std::vector<std::string> words;
    {
      std::string w;
      for (const char ch : s.substr(0, assign)) {
        if (std::isspace(static_cast<unsigned char>(ch))) {
          if (!w.empty()) words.push_back(std::move(w)), w.clear();
        } else {
          w += ch;
        }
      }
      if (!w.empty()) words.push_back(std::move(w));
    }
    if (assign == std::string_view::npos || words.size() < 3) return bad(line, "a declaration is 'PERS type name := value'", s);
    const std::string& type = words[words.size() - 2];
    const std::string& name = words.back();
    Value v;
    std::string why;
    if (!Parser(s.substr(assign + 2)).value(v, why)) return bad(line, why, s);
    if (type == "robtarget") {
      Target t;
      if (!target_of(v, t, why)) return bad(line, why, s);
      named_[name] = t;
    } else if (type == "tooldata") {
      double p[3], q[4];
      if (v.kind != Value::Kind::kList || v.items.size() != 3 || v.items[1].kind != Value::Kind::kList || v.items[1].items.size() != 2 ||
          !numbers(v.items[1].items[0], 3, p) || !numbers(v.items[1].items[1], 4, q)) {
        return bad(line, "a tooldata is [robhold,[[x,y,z],[q1,q2,q3,q4]],load]", s);
      }
      const machine::Frame3 ours = machine::frame_of({r_.tcp_mm[0], r_.tcp_mm[1], r_.tcp_mm[2]},
                                                     {r_.tcp_quaternion[0], r_.tcp_quaternion[1], r_.tcp_quaternion[2], r_.tcp_quaternion[3]});
      const machine::Frame3 theirs = machine::frame_of({p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]});
      if (core::norm(ours.origin - theirs.origin) > 1e-3 || core::norm(ours.z - theirs.z) > 1e-5) {
        return bad(line, "the tool's TCP is not the machine file's robot.tcp", s);
      }
      tools_.push_back(name);
    } else if (type == "wobjdata") {
      if (v.kind != Value::Kind::kList || v.items.size() != 5 || v.items[2].kind != Value::Kind::kString || v.items[2].text != r_.positioner_unit) {
        return bad(line, fmt::format("the work object must move with the positioner \"{}\" (ufmec)", r_.positioner_unit), s);
      }
      for (const std::size_t k : {3u, 4u}) {
        double p[3], q[4];
        if (v.items[k].kind != Value::Kind::kList || v.items[k].items.size() != 2 || !numbers(v.items[k].items[0], 3, p) ||
            !numbers(v.items[k].items[1], 4, q) || std::hypot(p[0], p[1], p[2]) > 1e-9 || std::abs(q[0] - 1.0) > 1e-9) {
          return bad(line, "the work object's user and object frames must be identity: polyaxis's part frame on the positioner", s);
        }
      }
      wobjs_.push_back(name);
    }
    return {};
  }

  core::Status motion(std::string_view instr, const std::vector<Value>& args, std::uint64_t line, std::string_view s) {
    const bool arc = instr.rfind("Arc", 0) == 0;
    const std::size_t positional = arc ? 6 : 4;  // target, speed, [seam, weld,] zone, tool
    if (args.size() != positional + 1) return bad(line, fmt::format("{} target, speed, {}zone, tool \\WObj:=wobj", instr, arc ? "seam, weld, " : ""), s);
    Target t;
    std::string why;
    if (args[0].kind == Value::Kind::kName) {
      const auto it = named_.find(args[0].text);
      if (it == named_.end()) return bad(line, fmt::format("no robtarget '{}' declared", args[0].text), s);
      t = it->second;
    } else if (!target_of(args[0], t, why)) {
      return bad(line, why, s);
    }
    double speed[3];
    if (!speed_of(args[1], speed, why)) return bad(line, why, s);
    const Value& tool = args[positional - 1];
    const Value& wobj = args[positional];
    if (tool.kind != Value::Kind::kName || std::find(tools_.begin(), tools_.end(), tool.text) == tools_.end()) {
      return bad(line, "the tool is not a tooldata declared in the module", s);
    }
    if (wobj.kind != Value::Kind::kName || wobj.text.rfind("\\WObj:=", 0) != 0 ||
        std::find(wobjs_.begin(), wobjs_.end(), wobj.text.substr(7)) == wobjs_.end()) {
      return bad(line, "the move needs \\WObj:= a work object on the positioner declared in the module", s);
    }
    // The pose the positioner and the arm take: the tip's joints from the written angles; the arm
    // solved with the written configuration.
    MachinePose angles{};
    angles.a_or_b_deg = t.eax_a, angles.c_deg = t.eax_b;
    const machine::Frame3 part_tcp = machine::frame_of(t.pos, t.rot);
    const MachinePose to = machine::positioner_pose_for(m_, angles, t.pos);
    const machine::Frame3 world = machine::tcp_in_world(m_, to, part_tcp);
    const auto q = arm(world, t.conf);
    if (!q) return bad(line, fmt::format("the robot cannot take this target in configuration [{},{},{},{}]: {}", t.conf.cf1, t.conf.cf4, t.conf.cf6, t.conf.cfx,
                                         machine::robot_unreachable_reason(r_, world)),
                       s);
    if (cb_.target) cb_.target(line, to, s);
    WalkMove mv;
    mv.line = line, mv.from = pos_, mv.to = to;
    mv.process_on = arc ? (instr != "ArcLStart") : on_;
    mv.layer = layer_, mv.region = region_;
    mv.tool_space = true;
    mv.tip_from = tip_, mv.tip_to = t.pos, mv.axis_from = axis_, mv.axis_to = part_tcp.z * -1.0;
    if (instr == "MoveJ") mv.robot_joint = true, mv.q_from = q_, mv.q_to = *q;
    mv.arm_to = *q;
    mv.feed = 60.0 * speed[0];
    mv.f_word = mv.feed;
    if (have_) {
      const double tip_mm = core::norm(mv.tip_to - mv.tip_from);
      const double turn_deg = std::atan2(core::norm(core::cross(mv.axis_from, mv.axis_to)), core::dot(mv.axis_from, mv.axis_to)) * 180.0 / M_PI;
      mv.l_xyz_mm = core::norm(Vec3{to.x_mm - pos_.x_mm, to.y_mm - pos_.y_mm, to.z_mm - pos_.z_mm});
      mv.d_tilt_deg = std::abs(to.a_or_b_deg - pos_.a_or_b_deg);
      mv.d_c_deg = std::abs(to.c_deg - pos_.c_deg);
      // The slowest of the TCP over the part, its turn and the positioner's axes sets the time.
      mv.time_min = std::max({tip_mm / speed[0], turn_deg / speed[1], std::max(mv.d_tilt_deg, mv.d_c_deg) / speed[2]}) / 60.0;
      if (tip_mm > 0.0 || turn_deg > 0.0 || mv.d_tilt_deg > 0.0 || mv.d_c_deg > 0.0) {
        if (cb_.move) cb_.move(mv);
      }
    } else {
      mv.from_known = false;
      if (cb_.move) cb_.move(mv);
    }
    pos_ = to, tip_ = t.pos, axis_ = mv.axis_to, q_ = *q, have_ = true;
    if (arc) on_ = instr != "ArcLEnd";
    return {};
  }

  // The arm's joints for WORLD in configuration CONF (its cfx), nearest the last joints.
  std::optional<machine::RobotJoints> arm(const machine::Frame3& world, const machine::RobotConfiguration& conf) const {
    std::optional<machine::RobotJoints> best;
    double best_d = INFINITY;
    for (const auto& s : machine::robot_solutions(r_, world, have_ ? &q_ : nullptr)) {
      if (s.conf.cfx != conf.cfx) continue;
      double d = 0.0;
      for (std::size_t k = 0; k < 6; ++k) d = std::max(d, std::abs(s.q[k] - q_[k]));
      if (d < best_d) best_d = d, best = s.q;
    }
    return best;
  }

  const machine::MachineConfig& m_;
  const machine::RobotCell& r_;
  const process::ProcessConfig* p_;
  const WalkCallbacks& cb_;
  bool module_ = false, in_proc_ = false, end_ = false, block_word_seen_ = false;
  std::map<std::string, Target> named_;
  std::vector<std::string> tools_, wobjs_;
  std::int64_t layer_ = -1, region_ = -1;
  bool on_ = false, have_ = false;
  MachinePose pos_{};
  Vec3 tip_{}, axis_{0.0, 0.0, 1.0};
  machine::RobotJoints q_{};
};

}  // namespace

core::Status walk_rapid(const machine::MachineConfig& machine, std::string_view text, const process::ProcessConfig* process,
                        const WalkCallbacks& callbacks, bool* program_end) {
  if (!machine.robot) return make_error(ErrorCode::kUsage, fmt::format("machine '{}' has no robot to read a RAPID module for", machine.name));
  RapidWalk walk(machine, process, callbacks);
  return walk.run(text, program_end);
}

}  // namespace polyaxis::verify::detail
