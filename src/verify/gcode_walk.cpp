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
      const auto [ptr, ec] = std::from_chars(first, line.data() + i, v);
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
      const auto [ptr, ec] = std::from_chars(first, line.data() + i, v);
      if (digits == 0 || ec != std::errc() || ptr != line.data() + i || !std::isfinite(v)) {
        why = fmt::format("'{}' is not a letter followed by a number", line.substr(start, std::max<std::size_t>(i - start, 1)));
        return std::nullopt;
      }
      if (std::abs(v) > kMaxWordMagnitude) {
        why = fmt::format("'{}' is beyond ±{:g}: no position or feed of a machine", line.substr(start, i - start), kMaxWordMagnitude);
        return std::nullopt;
      }
      words.push_back({static_cast<char>(std::toupper(static_cast<unsigned char>(ch))), v, line.substr(start, i - start)});
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
      if (ch != ' ' && ch != '\t') s += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
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

core::Status walk_gcode(const machine::MachineConfig& m, std::string_view gcode, const process::ProcessConfig* process,
                        const WalkCallbacks& cb, bool* program_end_out) {
  if (m.post == machine::PostDialect::kAbbRapid) return walk_rapid(m, gcode, process, cb, program_end_out);
  if (m.post == machine::PostDialect::k3mfToolpath) return walk_toolpath_3mf(m, gcode, cb, program_end_out);
  const bool five = machine::has_rotary_axes(m.kind);
  const char tilt = machine::tilt_axis_letter(m.kind);
  bool program_end = false;
  std::int64_t layer = -1, region = -1;
  MachinePose pos{};
  bool have_position = false;  // false until the first motion block: the machine is anywhere
  int motion_mode = -1;        // 0 or 1 once set
  bool inverse_time = false;
  double feed = 0.0;
  bool process_on = false;
  // Sinumerik TRAORI: the tip and the tool vector (modal), and whether TRAORI is on.
  const bool sinumerik = m.post == machine::PostDialect::kSiemensTraori;
  bool traori = false;
  // ISO under tool centre point control (post iso-tcp): X Y Z the tip once G43.4 is on.
  const bool iso_tcp = m.post == machine::PostDialect::kIsoTcp;
  bool tcp = false;
  MachinePose angles{};
  Vec3 tip{}, vec{0.0, 0.0, 1.0};

  std::uint64_t line_no = 0;
  std::size_t at = 0;
  while (at <= gcode.size() && !program_end) {
    const std::size_t nl = gcode.find('\n', at);
    const std::string_view line = gcode.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
    at = nl == std::string_view::npos ? gcode.size() + 1 : nl + 1;
    ++line_no;
    auto bad = [&](const std::string& why) {
      return make_error(ErrorCode::kInvalidInput, fmt::format("G-code line {}: {}: {}", line_no, why, line));
    };
    std::string why;
    if (sinumerik) {
      // TRAORI's control words stand alone on their lines.
      std::string_view word = line.substr(0, line.find(';'));
      while (!word.empty() && (word.back() == ' ' || word.back() == '\t' || word.back() == '\r')) word.remove_suffix(1);
      while (!word.empty() && (word.front() == ' ' || word.front() == '\t')) word.remove_prefix(1);
      if (word == "TRAORI" || word == "TRAFOOF") {
        traori = word == "TRAORI";
        continue;
      }
      if (word == "ORIWKS" || word == "ORIVECT") continue;
    }
    {
      // A tape's "%" start and end lines.
      std::string_view word = line;
      while (!word.empty() && (word.back() == ' ' || word.back() == '\t' || word.back() == '\r')) word.remove_suffix(1);
      while (!word.empty() && (word.front() == ' ' || word.front() == '\t')) word.remove_prefix(1);
      if (word == "%") continue;
    }
    const auto words = tokenize(line, why, sinumerik);
    if (!words) return bad(why);
    if (words->empty()) {
      layer_comment(line, layer, region);
      continue;
    }

    if (process != nullptr) {
      const std::string text = block_text(*words);
      if (text == process->process_on) process_on = true;
      if (text == process->process_off) process_on = false;
    }
    std::optional<int> block_motion;
    bool dwell = false;
    std::array<std::optional<double>, 6> axis{};  // X Y Z A B C
    std::optional<double> f_word;
    bool vector_word = false;
    std::array<std::optional<double>, 3> vector_words{};  // A3= B3= C3=
    for (const Word& w : *words) {
      switch (w.letter) {
        case 'G': {
          const double g = w.value;
          if (g == 0.0 || g == 1.0) {
            if (block_motion || dwell) return bad("two motion codes in one block");
            block_motion = static_cast<int>(g);
          } else if (g == 4.0) {
            if (block_motion) return bad("two motion codes in one block");
            dwell = true;
          } else if (g == 93.0) {
            inverse_time = true;
          } else if (g == 94.0) {
            inverse_time = false;
          } else if (g == 17.0 || g == 21.0 || g == 90.0 || (sinumerik && g == 71.0)) {
            // the only plane, unit and distance modes the writer uses
          } else if (iso_tcp && (w.text.substr(1) == "43.4" || g == 49.0)) {
            tcp = g != 49.0;
          } else {
            return bad(fmt::format("G{} is not supported (the simulator reads G0 G1 G4 G17 G21 G90 G93 G94{})", w.text.substr(1),
                                   iso_tcp ? " G43.4 G49" : ""));
          }
          break;
        }
        case 'M':
          if (w.value == 2.0 || w.value == 30.0) program_end = true;
          break;
        case 'X': axis[0] = w.value; break;
        case 'Y': axis[1] = w.value; break;
        case 'Z': axis[2] = w.value; break;
        case 'a':
        case 'b':
        case 'c':
          if (!traori) return bad("a tool vector word (A3= B3= C3=) without TRAORI");
          vector_words[static_cast<std::size_t>(w.letter - 'a')] = w.value;
          vector_word = true;
          break;
        case 'A':
        case 'B':
        case 'C': {
          if (sinumerik) return bad(fmt::format("{} word: under TRAORI the program gives the tool vector (A3= B3= C3=), not the axes", w.letter));
          if (!five || (w.letter != 'C' && w.letter != tilt)) {
            return bad(fmt::format("{} word, but machine '{}' ({}) has no {} axis", w.letter, m.name,
                                   machine::kinematics_name(m.kind), w.letter));
          }
          axis[static_cast<std::size_t>(3 + (w.letter - 'A'))] = w.value;
          break;
        }
        case 'F':
          if (!(w.value > 0.0)) return bad("F must be > 0");
          f_word = w.value;
          break;
        case 'H':
          if (!iso_tcp) return bad("unsupported word 'H'");
          break;
        case 'P':
        case 'S':
        case 'N': break;
        default: return bad(fmt::format("unsupported word '{}'", w.letter));
      }
    }
    // A Sinumerik dwell gives its seconds as F (the modal feed is kept).
    if (f_word && !(sinumerik && dwell)) feed = *f_word;
    if (block_motion) motion_mode = *block_motion;
    const bool has_axis = vector_word || std::any_of(axis.begin(), axis.end(), [](const auto& v) { return v.has_value(); });
    if (dwell) {
      double seconds = 0.0;
      for (const Word& w : *words) {
        if (w.letter == (sinumerik ? 'F' : iso_tcp ? 'X' : 'P')) seconds = w.value;
      }
      if (cb.dwell) cb.dwell(line_no, seconds, process_on);
      continue;
    }
    if (!has_axis) continue;
    if (motion_mode < 0) return bad("axis words without G0 or G1 in effect");

    if (sinumerik) {
      if (!traori) return bad("motion without TRAORI: the program gives the tip and the tool vector");
      const Vec3 tip_from = tip, vec_from = vec;
      if (axis[0]) tip.x = *axis[0];
      if (axis[1]) tip.y = *axis[1];
      if (axis[2]) tip.z = *axis[2];
      if (vector_words[0]) vec.x = *vector_words[0];
      if (vector_words[1]) vec.y = *vector_words[1];
      if (vector_words[2]) vec.z = *vector_words[2];
      if (!(core::norm(vec) > 0.0)) return bad("a zero tool vector");
      auto target = machine::inverse(m, tip, vec, have_position ? &pos : nullptr);
      if (!target) return make_error(target.error().code, fmt::format("G-code line {}: {}: {}", line_no, target.error().message, line));
      const bool rapid = motion_mode == 0;
      if (!rapid && !(feed > 0.0)) return bad("feed move without a feed rate (F)");
      if (cb.target) cb.target(line_no, target.value(), line);
      WalkMove mv;
      mv.line = line_no, mv.from = pos, mv.to = target.value(), mv.rapid = rapid, mv.f_word = f_word, mv.feed = feed;
      mv.process_on = process_on, mv.layer = layer, mv.region = region;
      mv.tool_space = true;
      mv.tip_from = tip_from, mv.tip_to = tip, mv.axis_from = core::normalized(vec_from), mv.axis_to = core::normalized(vec);
      if (!have_position) {
        mv.from_known = false;
        if (cb.move) cb.move(mv);
        pos = target.value();
        have_position = true;
        continue;
      }
      const double tip_mm = core::norm(tip - tip_from);
      const double turn_deg = std::atan2(core::norm(core::cross(mv.axis_from, mv.axis_to)), core::dot(mv.axis_from, mv.axis_to)) * 180.0 / M_PI;
      if (tip_mm == 0.0 && turn_deg == 0.0) continue;
      const MachinePose& to = target.value();
      mv.l_xyz_mm = norm(Vec3{to.x_mm - pos.x_mm, to.y_mm - pos.y_mm, to.z_mm - pos.z_mm});
      mv.d_tilt_deg = std::abs(to.a_or_b_deg - pos.a_or_b_deg);
      mv.d_c_deg = std::abs(to.c_deg - pos.c_deg);
      // F is the tip's path feed; a block turning the tool alone moves at its angle per minute.
      if (!rapid) mv.time_min = tip_mm > 0.0 ? tip_mm / feed : turn_deg / feed;
      if (cb.move) cb.move(mv);
      pos = to;
      continue;
    }

    if (iso_tcp) {
      if (!tcp) return bad("motion without G43.4: the program gives the tip, which needs tool centre point control");
      const Vec3 tip_from = tip;
      const MachinePose angles_from = angles;
      if (axis[0]) tip.x = *axis[0];
      if (axis[1]) tip.y = *axis[1];
      if (axis[2]) tip.z = *axis[2];
      if (axis[3]) angles.a_or_b_deg = *axis[3];
      if (axis[4]) angles.a_or_b_deg = *axis[4];
      if (axis[5]) angles.c_deg = *axis[5];
      const auto joints = machine::joints_for_tip(m, tip, angles);
      if (!joints) return bad("no linear axis pose puts the tip there");
      const bool rapid = motion_mode == 0;
      if (!rapid && !(feed > 0.0)) return bad("feed move without a feed rate (F)");
      if (cb.target) cb.target(line_no, *joints, line);
      WalkMove mv;
      mv.line = line_no, mv.from = pos, mv.to = *joints, mv.rapid = rapid, mv.f_word = f_word, mv.feed = feed;
      mv.process_on = process_on, mv.layer = layer, mv.region = region;
      mv.tool_space = true, mv.rotary_linear = true;
      mv.tip_from = tip_from, mv.tip_to = tip, mv.axis_from = axis_at(m, angles_from), mv.axis_to = axis_at(m, angles);
      if (!have_position) {
        mv.from_known = false;
        if (cb.move) cb.move(mv);
        pos = *joints;
        have_position = true;
        continue;
      }
      const double tip_mm = core::norm(tip - tip_from);
      mv.l_xyz_mm = norm(Vec3{joints->x_mm - pos.x_mm, joints->y_mm - pos.y_mm, joints->z_mm - pos.z_mm});
      mv.d_tilt_deg = std::abs(joints->a_or_b_deg - pos.a_or_b_deg);
      mv.d_c_deg = std::abs(joints->c_deg - pos.c_deg);
      const double l_rot = std::hypot(mv.d_tilt_deg, mv.d_c_deg);
      if (tip_mm == 0.0 && l_rot == 0.0) continue;
      // F is the tip's feed over the part; a block turning the axes alone moves at degrees per minute.
      if (!rapid) mv.time_min = tip_mm > 0.0 ? tip_mm / feed : l_rot / feed;
      if (cb.move) cb.move(mv);
      pos = *joints;
      continue;
    }

    MachinePose target = pos;
    if (axis[0]) target.x_mm = *axis[0];
    if (axis[1]) target.y_mm = *axis[1];
    if (axis[2]) target.z_mm = *axis[2];
    if (axis[3]) target.a_or_b_deg = *axis[3];
    if (axis[4]) target.a_or_b_deg = *axis[4];
    if (axis[5]) target.c_deg = *axis[5];

    const bool rapid = motion_mode == 0;
    if (!rapid && (inverse_time ? !f_word : !(feed > 0.0))) {
      return bad(inverse_time ? "G93 needs F on every feed move" : "feed move without a feed rate (F)");
    }
    if (cb.target) cb.target(line_no, target, line);
    WalkMove mv;
    mv.line = line_no;
    mv.from = pos;
    mv.to = target;
    mv.rapid = rapid;
    mv.f_word = f_word;
    mv.feed = feed;
    mv.inverse_time = inverse_time;
    mv.process_on = process_on;
    mv.layer = layer;
    mv.region = region;
    if (!have_position) {
      mv.from_known = false;
      if (cb.move) cb.move(mv);
      pos = target;
      have_position = true;
      continue;
    }
    mv.l_xyz_mm = norm(Vec3{target.x_mm - pos.x_mm, target.y_mm - pos.y_mm, target.z_mm - pos.z_mm});
    mv.d_tilt_deg = std::abs(target.a_or_b_deg - pos.a_or_b_deg);
    mv.d_c_deg = std::abs(target.c_deg - pos.c_deg);
    const double l_rot = std::hypot(mv.d_tilt_deg, mv.d_c_deg);
    if (mv.l_xyz_mm == 0.0 && l_rot == 0.0) continue;
    if (!rapid) {
      // Duration (minutes) as LinuxCNC reads F: XYZ path speed, else rotary speed, or 1/F in G93.
      mv.time_min = inverse_time ? 1.0 / *f_word : (mv.l_xyz_mm > 0.0 ? mv.l_xyz_mm / feed : l_rot / feed);
    }
    if (cb.move) cb.move(mv);
    pos = target;
  }
  if (program_end_out != nullptr) *program_end_out = program_end;
  return {};
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
