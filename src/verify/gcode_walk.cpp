#include "gcode_walk.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "polyaxis/core/progress.h"

namespace polyaxis::verify::detail {
namespace {
// The upper case of an ASCII letter (the text is G-code: no locale applies).
char ascii_upper(char ch) { return ch >= 'a' && ch <= 'z' ? static_cast<char>(ch - 'a' + 'A') : ch; }

// Digits of a number read exactly as an integer (below 2^53) over a power of ten that is exact
// as a double: then one division rounds correctly, as from_chars does.
constexpr int kExactDigits = 15;
constexpr int kExactPowers = 22;


using core::ErrorCode;
using core::make_error;
using core::Vec3;
using machine::MachinePose;

// A word beyond this (mm, degrees, mm/min, seconds) is no position, feed or dwell of a machine:
// refused, so that no move asks the readers for billions of samples.
constexpr double kMaxWordMagnitude = 1e6;

struct Word {
  char letter;
  double value;
  std::string_view text;  // as written, e.g. "P0"
};

// The words of one line, comments removed; nullopt and WHY on malformed text.
// Sinumerik: the tool vector's words A3= B3= C3=, read as the letters 'a', 'b', 'c'.
std::optional<std::vector<Word>> tokenize(std::string_view line, std::string& why, bool sinumerik = false) {
  std::vector<Word> words;
  std::size_t i = 0;
  while (i < line.size()) {
    const char ch = line[i];
    if (sinumerik && (ch == 'A' || ch == 'B' || ch == 'C') && line.substr(i + 1, 2) == "3=") {
      const std::size_t start = i;
      i += 3;
      const std::size_t num = i;
      if (i < line.size() && (line[i] == '+' || line[i] == '-')) ++i;
      while (i < line.size() && (std::isdigit(static_cast<unsigned char>(line[i])) || line[i] == '.')) ++i;
      double v = 0.0;
      const char* first = line.data() + num + (num < line.size() && line[num] == '+' ? 1 : 0);
      const auto [ptr, ec] = read_number(first, line.data() + i, v);
      if (i == num || ec != std::errc() || ptr != line.data() + i || !std::isfinite(v) || std::abs(v) > kMaxWordMagnitude) {
        why = fmt::format("'{}' is not a tool vector component", line.substr(start, std::max<std::size_t>(i - start, 1)));
        return std::nullopt;
      }
      words.push_back({static_cast<char>(ch - 'A' + 'a'), v, line.substr(start, i - start)});
      continue;
    }
    if (ch == ' ' || ch == '\t' || ch == '\r') {
      ++i;
    } else if (ch == ';') {
      break;
    } else if (ch == '(') {
      const std::size_t close = line.find(')', i);
      if (close == std::string_view::npos) {
        why = "unclosed comment";
        return std::nullopt;
      }
      i = close + 1;
    } else if (std::isalpha(static_cast<unsigned char>(ch))) {
      const std::size_t start = i++;
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t num = i;
      if (i < line.size() && (line[i] == '+' || line[i] == '-')) ++i;
      std::size_t digits = 0;
      while (i < line.size() && (std::isdigit(static_cast<unsigned char>(line[i])) || line[i] == '.')) {
        digits += std::isdigit(static_cast<unsigned char>(line[i])) ? 1 : 0;
        ++i;
      }
      double v = 0.0;
      const char* first = line.data() + num + (num < line.size() && line[num] == '+' ? 1 : 0);
      const auto [ptr, ec] = read_number(first, line.data() + i, v);
      if (digits == 0 || ec != std::errc() || ptr != line.data() + i || !std::isfinite(v)) {
        why = fmt::format("'{}' is not a letter followed by a number", line.substr(start, std::max<std::size_t>(i - start, 1)));
        return std::nullopt;
      }
      if (std::abs(v) > kMaxWordMagnitude) {
        why = fmt::format("'{}' is beyond ±{:g}: no position or feed of a machine", line.substr(start, i - start), kMaxWordMagnitude);
        return std::nullopt;
      }
      words.push_back({ascii_upper(ch), v, line.substr(start, i - start)});
    } else {
      why = fmt::format("unexpected character '{}'", ch);
      return std::nullopt;
    }
  }
  return words;
}


std::string block_text(const std::vector<Word>& words) {
  std::string s;
  for (const Word& w : words) {
    if (!s.empty()) s += ' ';
    for (const char ch : w.text) {
      if (ch != ' ' && ch != '\t') s += ascii_upper(ch);
    }
  }
  return s;
}


// "(layer N region R ...)" at the start of a line: N and R.
bool layer_comment(std::string_view line, std::int64_t& layer, std::int64_t& region) {
  std::size_t i = 0;
  while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
  constexpr std::string_view kHead = "(layer ", kSinumerikHead = "; layer ";
  if (line.substr(i, kHead.size()) == kHead) {
    i += kHead.size();
  } else if (line.substr(i, kSinumerikHead.size()) == kSinumerikHead) {
    i += kSinumerikHead.size();
  } else {
    return false;
  }
  auto number = [&](std::int64_t& out) {
    const auto [ptr, ec] = std::from_chars(line.data() + i, line.data() + line.size(), out);
    if (ec != std::errc()) return false;
    i = static_cast<std::size_t>(ptr - line.data());
    return true;
  };
  std::int64_t l = 0, r = 0;
  if (!number(l)) return false;
  constexpr std::string_view kRegion = " region ";
  if (line.substr(i, kRegion.size()) != kRegion) return false;
  i += kRegion.size();
  if (!number(r)) return false;
  layer = l, region = r;
  return true;
}

// The tool axis (part frame) with the rotary axes at POSE's.
Vec3 axis_at(const machine::MachineConfig& m, MachinePose pose) {
  pose.x_mm = pose.y_mm = pose.z_mm = 0.0;
  return core::normalized(machine::forward(m, pose).tool_axis_part);
}

}  // namespace

namespace {

// One block's words as read (the modal state is the walker's).
struct Block {
  std::optional<int> motion;                       // G0 or G1
  bool dwell = false;                              // G4
  std::array<std::optional<double>, 6> axis{};     // X Y Z A B C
  std::optional<double> f_word;
  bool vector_word = false;
  std::array<std::optional<double>, 3> vector{};   // A3= B3= C3=
};

// The G-code dialects' reader: the lines in order, their modal state, and a move for each motion
// block in the machine's dialect (joint words, TRAORI's tip and vector, or the tip and rotary
// words under G43.4).
class GcodeWalker {
 public:
  GcodeWalker(const machine::MachineConfig& m, const process::ProcessConfig* process, const WalkCallbacks& cb)
      : m_(m), process_(process), cb_(cb) {}

  core::Status run(std::string_view gcode, bool* program_end_out) {
    std::size_t at = 0;
    while (at <= gcode.size() && !program_end_) {
      const std::size_t nl = gcode.find('\n', at);
      line_ = gcode.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
      at = nl == std::string_view::npos ? gcode.size() + 1 : nl + 1;
      ++line_no_;
      if (auto st = read_line(); !st) return st;
    }
    if (program_end_out != nullptr) *program_end_out = program_end_;
    return {};
  }

 private:
  core::Error bad(const std::string& why) const {
    return make_error(ErrorCode::kInvalidInput, fmt::format("G-code line {}: {}: {}", line_no_, why, line_));
  }

  // LINE without its leading and trailing blanks.
  static std::string_view trimmed(std::string_view word) {
    while (!word.empty() && (word.back() == ' ' || word.back() == '\t' || word.back() == '\r')) word.remove_suffix(1);
    while (!word.empty() && (word.front() == ' ' || word.front() == '\t')) word.remove_prefix(1);
    return word;
  }

  core::Status read_line() {
    if (sinumerik_) {
      // TRAORI's control words stand alone on their lines.
      const std::string_view word = trimmed(line_.substr(0, line_.find(';')));
      if (word == "TRAORI" || word == "TRAFOOF") {
        traori_ = word == "TRAORI";
        return {};
      }
      if (word == "ORIWKS" || word == "ORIVECT") return {};
    }
    if (trimmed(line_) == "%") return {};  // a tape's start and end lines
    std::string why;
    const auto words = tokenize(line_, why, sinumerik_);
    if (!words) return bad(why);
    if (words->empty()) {
      layer_comment(line_, layer_, region_);
      return {};
    }
    // The block's text starts with its first word's letter: most blocks are no process switch.
    const char head = ascii_upper(words->front().text.front());
    if (process_ != nullptr && (head == process_head_[0] || head == process_head_[1])) {
      const std::string text = block_text(*words);
      if (text == process_->process_on) process_on_ = true;
      if (text == process_->process_off) process_on_ = false;
    }
    Block b;
    if (auto st = read_words(*words, b); !st) return st;
    // A Sinumerik dwell gives its seconds as F (the modal feed is kept).
    if (b.f_word && !(sinumerik_ && b.dwell)) feed_ = *b.f_word;
    if (b.motion) motion_mode_ = *b.motion;
    if (b.dwell) {
      double seconds = 0.0;
      for (const Word& w : *words) {
        if (w.letter == (sinumerik_ ? 'F' : iso_tcp_ ? 'X' : 'P')) seconds = w.value;
      }
      if (cb_.dwell) cb_.dwell(line_no_, seconds, process_on_);
      return {};
    }
    const bool has_axis = b.vector_word || std::any_of(b.axis.begin(), b.axis.end(), [](const auto& v) { return v.has_value(); });
    if (!has_axis) return {};
    if (motion_mode_ < 0) return bad("axis words without G0 or G1 in effect");
    if (sinumerik_) return traori_move(b);
    if (iso_tcp_) return tcp_move(b);
    return joint_move(b);
  }

  core::Status read_g(const Word& w, Block& b) {
    const double g = w.value;
    if (g == 0.0 || g == 1.0) {
      if (b.motion || b.dwell) return bad("two motion codes in one block");
      b.motion = static_cast<int>(g);
    } else if (g == 4.0) {
      if (b.motion) return bad("two motion codes in one block");
      b.dwell = true;
    } else if (g == 93.0) {
      inverse_time_ = true;
    } else if (g == 94.0) {
      inverse_time_ = false;
    } else if (g == 17.0 || g == 21.0 || g == 90.0 || (sinumerik_ && g == 71.0)) {
      // the only plane, unit and distance modes the writer uses
    } else if (g == 64.0 && !sinumerik_ && !iso_tcp_) {
      // path blending (G64 P): the controller's, not the path's
    } else if (iso_tcp_ && (w.text.substr(1) == "43.4" || g == 49.0)) {
      tcp_ = g != 49.0;
    } else {
      return bad(fmt::format("G{} is not supported (the simulator reads G0 G1 G4 G17 G21 G90 G93 G94{})", w.text.substr(1),
                             iso_tcp_ ? " G43.4 G49" : sinumerik_ ? "" : " G64"));
    }
    return {};
  }

  core::Status read_words(const std::vector<Word>& words, Block& b) {
    for (const Word& w : words) {
      switch (w.letter) {
        case 'G':
          if (auto st = read_g(w, b); !st) return st;
          break;
        case 'M':
          if (w.value == 2.0 || w.value == 30.0) program_end_ = true;
          break;
        case 'X': b.axis[0] = w.value; break;
        case 'Y': b.axis[1] = w.value; break;
        case 'Z': b.axis[2] = w.value; break;
        case 'a':
        case 'b':
        case 'c':
          if (!traori_) return bad("a tool vector word (A3= B3= C3=) without TRAORI");
          b.vector[static_cast<std::size_t>(w.letter - 'a')] = w.value;
          b.vector_word = true;
          break;
        case 'A':
        case 'B':
        case 'C':
          if (sinumerik_) return bad(fmt::format("{} word: under TRAORI the program gives the tool vector (A3= B3= C3=), not the axes", w.letter));
          if (!five_ || (w.letter != 'C' && w.letter != tilt_)) {
            return bad(fmt::format("{} word, but machine '{}' ({}) has no {} axis", w.letter, m_.name, machine::kinematics_name(m_.kind), w.letter));
          }
          b.axis[static_cast<std::size_t>(3 + (w.letter - 'A'))] = w.value;
          break;
        case 'F':
          if (!(w.value > 0.0)) return bad("F must be > 0");
          b.f_word = w.value;
          break;
        case 'H':
          if (!iso_tcp_) return bad("unsupported word 'H'");
          break;
        case 'P':
        case 'S':
        case 'N': break;
        default: return bad(fmt::format("unsupported word '{}'", w.letter));
      }
    }
    return {};
  }

  // The move to TO from where the machine is, with the block's modal state.
  WalkMove move_to(const MachinePose& to, const Block& b) const {
    WalkMove mv;
    mv.line = line_no_, mv.from = pos_, mv.to = to, mv.rapid = motion_mode_ == 0, mv.f_word = b.f_word, mv.feed = feed_;
    mv.inverse_time = inverse_time_, mv.process_on = process_on_, mv.layer = layer_, mv.region = region_;
    return mv;
  }

  // Sends MV and moves there: the first move as it is (its start unknown), the others with their
  // axis lengths unless nothing MOVES (then nothing is sent and the machine stays).
  void send(WalkMove& mv, bool moves) {
    if (!have_position_) {
      mv.from_known = false;
      if (cb_.move) cb_.move(mv);
    } else if (moves) {
      mv.l_xyz_mm = norm(Vec3{mv.to.x_mm - pos_.x_mm, mv.to.y_mm - pos_.y_mm, mv.to.z_mm - pos_.z_mm});
      mv.d_tilt_deg = std::abs(mv.to.a_or_b_deg - pos_.a_or_b_deg);
      mv.d_c_deg = std::abs(mv.to.c_deg - pos_.c_deg);
      if (cb_.move) cb_.move(mv);
    } else {
      return;
    }
    pos_ = mv.to;
    have_position_ = true;
  }

  // Sinumerik TRAORI: the tip and the tool vector.
  core::Status traori_move(const Block& b) {
    if (!traori_) return bad("motion without TRAORI: the program gives the tip and the tool vector");
    const Vec3 tip_from = tip_, vec_from = vec_;
    for (std::size_t k = 0; k < 3; ++k) {
      if (b.axis[k]) (k == 0 ? tip_.x : k == 1 ? tip_.y : tip_.z) = *b.axis[k];
      if (b.vector[k]) (k == 0 ? vec_.x : k == 1 ? vec_.y : vec_.z) = *b.vector[k];
    }
    if (!(core::norm(vec_) > 0.0)) return bad("a zero tool vector");
    auto target = machine::inverse(m_, tip_, vec_, have_position_ ? &pos_ : nullptr);
    if (!target) return make_error(target.error().code, fmt::format("G-code line {}: {}: {}", line_no_, target.error().message, line_));
    if (motion_mode_ != 0 && !(feed_ > 0.0)) return bad("feed move without a feed rate (F)");
    if (cb_.target) cb_.target(line_no_, target.value(), line_);
    WalkMove mv = move_to(target.value(), b);
    mv.inverse_time = false;
    mv.tool_space = true;
    mv.tip_from = tip_from, mv.tip_to = tip_, mv.axis_from = core::normalized(vec_from), mv.axis_to = core::normalized(vec_);
    const double tip_mm = core::norm(tip_ - tip_from);
    const double turn_deg = std::atan2(core::norm(core::cross(mv.axis_from, mv.axis_to)), core::dot(mv.axis_from, mv.axis_to)) * 180.0 / M_PI;
    // F is the tip's path feed; a block turning the tool alone moves at its angle per minute.
    if (!mv.rapid && have_position_) mv.time_min = tip_mm > 0.0 ? tip_mm / feed_ : turn_deg / feed_;
    send(mv, tip_mm != 0.0 || turn_deg != 0.0);
    return {};
  }

  // ISO under G43.4: the tip and the rotary axes' words.
  core::Status tcp_move(const Block& b) {
    if (!tcp_) return bad("motion without G43.4: the program gives the tip, which needs tool centre point control");
    const Vec3 tip_from = tip_;
    const MachinePose angles_from = angles_;
    for (std::size_t k = 0; k < 3; ++k) {
      if (b.axis[k]) (k == 0 ? tip_.x : k == 1 ? tip_.y : tip_.z) = *b.axis[k];
    }
    if (b.axis[3]) angles_.a_or_b_deg = *b.axis[3];
    if (b.axis[4]) angles_.a_or_b_deg = *b.axis[4];
    if (b.axis[5]) angles_.c_deg = *b.axis[5];
    const auto joints = machine::joints_for_tip(m_, tip_, angles_);
    if (!joints) return bad("no linear axis pose puts the tip there");
    if (motion_mode_ != 0 && !(feed_ > 0.0)) return bad("feed move without a feed rate (F)");
    if (cb_.target) cb_.target(line_no_, *joints, line_);
    WalkMove mv = move_to(*joints, b);
    mv.inverse_time = false;
    mv.tool_space = true, mv.rotary_linear = true;
    mv.tip_from = tip_from, mv.tip_to = tip_, mv.axis_from = axis_at(m_, angles_from), mv.axis_to = axis_at(m_, angles_);
    const double tip_mm = core::norm(tip_ - tip_from);
    const double l_rot = std::hypot(joints->a_or_b_deg - pos_.a_or_b_deg, joints->c_deg - pos_.c_deg);
    // F is the tip's feed over the part; a block turning the axes alone moves at degrees per minute.
    if (!mv.rapid && have_position_) mv.time_min = tip_mm > 0.0 ? tip_mm / feed_ : l_rot / feed_;
    send(mv, tip_mm != 0.0 || l_rot != 0.0);
    return {};
  }

  // LinuxCNC: the axes' joint values.
  core::Status joint_move(const Block& b) {
    MachinePose target = pos_;
    if (b.axis[0]) target.x_mm = *b.axis[0];
    if (b.axis[1]) target.y_mm = *b.axis[1];
    if (b.axis[2]) target.z_mm = *b.axis[2];
    if (b.axis[3]) target.a_or_b_deg = *b.axis[3];
    if (b.axis[4]) target.a_or_b_deg = *b.axis[4];
    if (b.axis[5]) target.c_deg = *b.axis[5];
    const bool rapid = motion_mode_ == 0;
    if (!rapid && (inverse_time_ ? !b.f_word : !(feed_ > 0.0))) {
      return bad(inverse_time_ ? "G93 needs F on every feed move" : "feed move without a feed rate (F)");
    }
    if (cb_.target) cb_.target(line_no_, target, line_);
    WalkMove mv = move_to(target, b);
    const double l_xyz = norm(Vec3{target.x_mm - pos_.x_mm, target.y_mm - pos_.y_mm, target.z_mm - pos_.z_mm});
    const double l_rot = std::hypot(target.a_or_b_deg - pos_.a_or_b_deg, target.c_deg - pos_.c_deg);
    if (!rapid && have_position_) {
      // Duration (minutes) as LinuxCNC reads F: XYZ path speed, else rotary speed, or 1/F in G93.
      mv.time_min = inverse_time_ ? 1.0 / *b.f_word : (l_xyz > 0.0 ? l_xyz / feed_ : l_rot / feed_);
    }
    send(mv, l_xyz != 0.0 || l_rot != 0.0);
    return {};
  }

  const machine::MachineConfig& m_;
  const process::ProcessConfig* process_;
  // The first characters of the process switches (block_text's, upper case; NUL for none).
  const std::array<char, 2> process_head_ = {process_ && !process_->process_on.empty() ? ascii_upper(process_->process_on.front()) : '\0',
                                             process_ && !process_->process_off.empty() ? ascii_upper(process_->process_off.front()) : '\0'};
  const WalkCallbacks& cb_;
  const bool five_ = machine::has_rotary_axes(m_.kind);
  const char tilt_ = machine::tilt_axis_letter(m_.kind);
  const bool sinumerik_ = m_.post == machine::PostDialect::kSiemensTraori;  // TRAORI: the tip and the tool vector
  const bool iso_tcp_ = m_.post == machine::PostDialect::kIsoTcp;           // G43.4: the tip and the rotary axes
  std::string_view line_;
  std::uint64_t line_no_ = 0;
  bool program_end_ = false;
  std::int64_t layer_ = -1, region_ = -1;
  MachinePose pos_{};
  bool have_position_ = false;  // false until the first motion block: the machine is anywhere
  int motion_mode_ = -1;        // 0 or 1 once set
  bool inverse_time_ = false;
  double feed_ = 0.0;
  bool process_on_ = false;
  bool traori_ = false, tcp_ = false;  // TRAORI on, G43.4 on
  Vec3 tip_{}, vec_{0.0, 0.0, 1.0};     // modal tip and tool vector (TRAORI, G43.4)
  MachinePose angles_{};                // modal rotary words under G43.4
};

}  // namespace

std::from_chars_result read_number(const char* first, const char* last, double& out) {
  static constexpr double kPowers[kExactPowers + 1] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const char* p = first;
  const bool minus = p < last && *p == '-';
  if (minus) ++p;
  std::uint64_t mantissa = 0;
  int significant = 0, decimals = 0;
  bool point = false, digit = false;
  for (; p < last; ++p) {
    const char c = *p;
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (c < '0' || c > '9') break;
    digit = true;
    decimals += point ? 1 : 0;
    if (mantissa == 0 && c == '0') continue;  // a leading zero is no significant digit
    mantissa = mantissa * 10 + static_cast<std::uint64_t>(c - '0');
    ++significant;
  }
  if (p != last || !digit || significant > kExactDigits || decimals > kExactPowers) return std::from_chars(first, last, out);
  const double v = static_cast<double>(mantissa) / kPowers[decimals];
  out = minus ? -v : v;
  return {p, std::errc()};
}

core::Status walk_gcode(const machine::MachineConfig& m, std::string_view gcode, const process::ProcessConfig* process,
                        const WalkCallbacks& cb, bool* program_end_out) {
  if (m.post == machine::PostDialect::kAbbRapid) return walk_rapid(m, gcode, process, cb, program_end_out);
  if (m.post == machine::PostDialect::k3mfToolpath) return walk_toolpath_3mf(m, gcode, cb, program_end_out);
  GcodeWalker walker(m, process, cb);
  return walker.run(gcode, program_end_out);
}

machine::MachineToolPose tool_at(const machine::MachineConfig& machine, const WalkMove& mv, double u) {
  if (!mv.tool_space) {
    const MachinePose p{mv.from.x_mm + (mv.to.x_mm - mv.from.x_mm) * u, mv.from.y_mm + (mv.to.y_mm - mv.from.y_mm) * u,
                        mv.from.z_mm + (mv.to.z_mm - mv.from.z_mm) * u, mv.from.a_or_b_deg + (mv.to.a_or_b_deg - mv.from.a_or_b_deg) * u,
                        mv.from.c_deg + (mv.to.c_deg - mv.from.c_deg) * u};
    return machine::forward(machine, p);
  }
  if (mv.robot_joint && machine.robot) {
    machine::RobotJoints q{};
    for (std::size_t k = 0; k < 6; ++k) q[k] = mv.q_from[k] + (mv.q_to[k] - mv.q_from[k]) * u;
    MachinePose angles{};
    angles.a_or_b_deg = mv.from.a_or_b_deg + (mv.to.a_or_b_deg - mv.from.a_or_b_deg) * u;
    angles.c_deg = mv.from.c_deg + (mv.to.c_deg - mv.from.c_deg) * u;
    return machine::part_tool_of(machine, angles, machine::robot_tcp_world(*machine.robot, q));
  }
  if (mv.rotary_linear) {
    // G43.4: the tip straight, the rotary axes linear.
    MachinePose angles = mv.from;
    angles.a_or_b_deg += (mv.to.a_or_b_deg - mv.from.a_or_b_deg) * u;
    angles.c_deg += (mv.to.c_deg - mv.from.c_deg) * u;
    return {mv.tip_from + (mv.tip_to - mv.tip_from) * u, axis_at(machine, angles)};
  }
  // The great circle from AXIS_FROM to AXIS_TO (ORIVECT), the tip straight.
  const Vec3 a = mv.axis_from, b = mv.axis_to;
  const double w = std::atan2(core::norm(core::cross(a, b)), core::dot(a, b));
  Vec3 axis = b;
  if (w < 1e-12) {
    axis = a;
  } else if (std::sin(w) > 1e-12) {
    axis = core::normalized(a * (std::sin((1.0 - u) * w) / std::sin(w)) + b * (std::sin(u * w) / std::sin(w)));
  }
  return {mv.tip_from + (mv.tip_to - mv.tip_from) * u, axis};
}

}  // namespace polyaxis::verify::detail
