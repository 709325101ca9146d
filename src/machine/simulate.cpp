#include "polyaxis/machine/simulate.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>

#include "polyaxis/core/progress.h"
#include "polyaxis/motion/kinematics.h"
#include "polyaxis/motion/segment.h"

namespace polyaxis::machine {

namespace {

using core::ErrorCode;
using core::make_error;
using core::Vec3;
using motion::MachinePose;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// Plan segments searched ahead of the last match: generous for subdivided moves, keeps cost linear.
constexpr std::size_t kPlanWindow = 64;
// Path length: a block is measured in pieces turning at most this much (degrees) each.
constexpr double kLengthStepDeg = 1.0;
// A feed above a limit by less than this fraction is the limit written with 4 decimals.
constexpr double kFeedLimitSlack = 1e-9;

struct Word {
  char letter;
  double value;
  std::string_view text;  // as written, e.g. "P0"
};

// The words of one line, comments removed; nullopt and WHY on malformed text.
std::optional<std::vector<Word>> tokenize(std::string_view line, std::string& why) {
  std::vector<Word> words;
  std::size_t i = 0;
  while (i < line.size()) {
    const char ch = line[i];
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
      words.push_back({static_cast<char>(std::toupper(static_cast<unsigned char>(ch))), v, line.substr(start, i - start)});
    } else {
      why = fmt::format("unexpected character '{}'", ch);
      return std::nullopt;
    }
  }
  return words;
}

// Angle (radians) from unit V to the great-circle arc from A to B (unit vectors).
double angle_to_arc(Vec3 v, Vec3 a, Vec3 b) {
  auto angle = [](Vec3 p, Vec3 q) { return std::atan2(norm(cross(p, q)), dot(p, q)); };
  const Vec3 n = cross(a, b);
  const double nn = norm(n);
  const double ends = std::min(angle(v, a), angle(v, b));
  if (nn < 1e-12) return ends;
  const Vec3 un = n / nn;
  const Vec3 w = v - un * dot(v, un);
  if (norm(w) < 1e-15) return ends;
  // W lies on the arc when it is between A and B as seen along N.
  if (dot(cross(a, w), un) >= 0.0 && dot(cross(w, b), un) >= 0.0) return std::asin(std::min(1.0, std::abs(dot(v, un))));
  return ends;
}

// A sample this close to a planned segment is on it (the written words are rounded to 0.1 µm).
constexpr double kOnPlanMm = 1e-3;

class PlanMatcher {
 public:
  explicit PlanMatcher(std::span<const ProgramPoint> plan) : plan_(plan) {}

  // Deviation of a sample (tip, axis) from the nearest planned segment near the last match.
  std::pair<double, double> deviation(Vec3 tip, Vec3 axis) {
    if (plan_.size() == 1) {
      const Vec3 a = normalized(plan_[0].tool_axis_part);
      return {norm(tip - plan_[0].tip_part_mm), std::atan2(norm(cross(axis, a)), dot(axis, a))};
    }
    const std::size_t segments = plan_.size() - 1;
    const std::size_t end = std::min(segments, cursor_ + kPlanWindow);
    double best = INFINITY;
    std::size_t best_j = cursor_;
    // The program follows the plan in order, and a path may come back to where it passed before
    // (a closed perimeter, the next layer above): the earliest segment the sample lies on wins,
    // else the nearest one in the window.
    for (std::size_t j = cursor_; j < end; ++j) {
      const double d = motion::distance_to_segment(tip, plan_[j].tip_part_mm, plan_[j + 1].tip_part_mm);
      if (d < best) {
        best = d;
        best_j = j;
      }
      if (d <= kOnPlanMm) break;
    }
    cursor_ = best_j;
    const double ang = angle_to_arc(axis, normalized(plan_[best_j].tool_axis_part), normalized(plan_[best_j + 1].tool_axis_part));
    return {best, ang};
  }

 private:
  std::span<const ProgramPoint> plan_;
  std::size_t cursor_ = 0;
};

void widen(AxisSpan& s, double v) {
  s.min = std::min(s.min, v);
  s.max = std::max(s.max, v);
}

MachinePose lerp(const MachinePose& a, const MachinePose& b, double u) {
  return {a.x_mm + (b.x_mm - a.x_mm) * u, a.y_mm + (b.y_mm - a.y_mm) * u, a.z_mm + (b.z_mm - a.z_mm) * u,
          a.a_or_b_deg + (b.a_or_b_deg - a.a_or_b_deg) * u, a.c_deg + (b.c_deg - a.c_deg) * u};
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

}  // namespace

core::Result<SimulationReport> simulate(const motion::MachineConfig& m, std::string_view gcode,
                                        std::span<const ProgramPoint> plan, const motion::ProcessConfig* process) {
  SimulationReport rep;
  rep.compared_with_plan = !plan.empty();
  PlanMatcher matcher(plan);
  const bool five = motion::has_rotary_axes(m.kind);
  const char tilt = motion::tilt_axis_letter(m.kind);

  MachinePose pos{};
  bool have_position = false;  // false until the first motion block: the machine is anywhere
  int motion_mode = -1;        // 0 or 1 once set
  bool inverse_time = false;
  double feed = 0.0;
  bool process_on = false;

  auto violation = [&](std::uint64_t line_no, const std::string& what) {
    ++rep.limit_violations;
    if (rep.violations.size() < kMaxReportedViolations) rep.violations.push_back(fmt::format("line {}: {}", line_no, what));
  };
  auto sample = [&](std::uint64_t line_no, const MachinePose& p) {
    if (!rep.compared_with_plan) return;
    const motion::MachineToolPose tp = motion::forward(m, p);
    const auto [d_tip, d_axis] = matcher.deviation(tp.tip_part_mm, tp.tool_axis_part);
    if (d_tip > rep.max_tip_deviation_mm) {
      rep.max_tip_deviation_mm = d_tip;
      rep.worst_tip_line = line_no;
    }
    rep.max_axis_deviation_deg = std::max(rep.max_axis_deviation_deg, d_axis * kDegPerRad);
  };

  std::uint64_t line_no = 0;
  std::size_t at = 0;
  core::Progress progress("simulate", gcode.size());  // bytes read
  while (at <= gcode.size() && !rep.program_end) {
    if ((line_no & 4095) == 0) progress.update(std::min(at, gcode.size()));
    const std::size_t nl = gcode.find('\n', at);
    const std::string_view line = gcode.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
    at = nl == std::string_view::npos ? gcode.size() + 1 : nl + 1;
    ++line_no;
    auto bad = [&](const std::string& why) {
      return make_error(ErrorCode::kInvalidInput, fmt::format("G-code line {}: {}: {}", line_no, why, line));
    };
    std::string why;
    const auto words = tokenize(line, why);
    if (!words) return bad(why);
    if (words->empty()) continue;

    if (process != nullptr) {
      const std::string text = block_text(*words);
      if (text == process->process_on) process_on = true;
      if (text == process->process_off) process_on = false;
    }
    std::optional<int> block_motion;
    bool dwell = false;
    std::array<std::optional<double>, 6> axis{};  // X Y Z A B C
    std::optional<double> f_word;
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
          } else if (g == 17.0 || g == 21.0 || g == 90.0) {
            // the only plane, unit and distance modes the writer uses
          } else {
            return bad(fmt::format("G{} is not supported (the simulator reads G0 G1 G4 G17 G21 G90 G93 G94)", w.text.substr(1)));
          }
          break;
        }
        case 'M':
          if (w.value == 2.0 || w.value == 30.0) rep.program_end = true;
          break;
        case 'X': axis[0] = w.value; break;
        case 'Y': axis[1] = w.value; break;
        case 'Z': axis[2] = w.value; break;
        case 'A':
        case 'B':
        case 'C': {
          if (!five || (w.letter != 'C' && w.letter != tilt)) {
            return bad(fmt::format("{} word, but machine '{}' ({}) has no {} axis", w.letter, m.name,
                                   motion::kinematics_name(m.kind), w.letter));
          }
          axis[static_cast<std::size_t>(3 + (w.letter - 'A'))] = w.value;
          break;
        }
        case 'F':
          if (!(w.value > 0.0)) return bad("F must be > 0");
          f_word = w.value;
          break;
        case 'P':
        case 'S':
        case 'N': break;
        default: return bad(fmt::format("unsupported word '{}'", w.letter));
      }
    }
    if (f_word) feed = *f_word;
    if (block_motion) motion_mode = *block_motion;
    const bool has_axis = std::any_of(axis.begin(), axis.end(), [](const auto& v) { return v.has_value(); });
    if (!has_axis || dwell) continue;
    if (motion_mode < 0) return bad("axis words without G0 or G1 in effect");

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
    widen(rep.x_mm, target.x_mm);
    widen(rep.y_mm, target.y_mm);
    widen(rep.z_mm, target.z_mm);
    if (five) {
      widen(rep.a_or_b_deg, target.a_or_b_deg);
      widen(rep.c_deg, target.c_deg);
    }
    if (std::string v = motion::limit_violation(m, target); !v.empty()) violation(line_no, v);

    if (!have_position) {
      // From an unknown position: only where it ends is known.
      ++rep.moves;
      if (rapid) ++rep.rapid_moves;
      sample(line_no, target);
      pos = target;
      have_position = true;
      continue;
    }
    const double l_xyz = norm(Vec3{target.x_mm - pos.x_mm, target.y_mm - pos.y_mm, target.z_mm - pos.z_mm});
    const double d_tilt = std::abs(target.a_or_b_deg - pos.a_or_b_deg), d_c = std::abs(target.c_deg - pos.c_deg);
    const double l_rot = std::hypot(d_tilt, d_c);
    if (l_xyz == 0.0 && l_rot == 0.0) continue;
    ++rep.moves;
    if (rapid) ++rep.rapid_moves;

    if (!rapid) {
      // Duration (minutes) as LinuxCNC reads F: XYZ path speed, else rotary speed, or 1/F in G93.
      const double t_min = inverse_time ? 1.0 / *f_word : (l_xyz > 0.0 ? l_xyz / feed : l_rot / feed);
      rep.feed_time_s += t_min * 60.0;
      if (l_xyz / t_min > m.feed.linear_max_mm_min * (1.0 + kFeedLimitSlack)) {
        violation(line_no, fmt::format("XYZ feed {:.4f} mm/min is above the maximum {} mm/min", l_xyz / t_min,
                                       m.feed.linear_max_mm_min));
      }
      const double rot_speed = (l_xyz > 0.0 || inverse_time) ? std::max(d_tilt, d_c) / t_min : feed;
      if (rot_speed > m.feed.rotary_max_deg_min * (1.0 + kFeedLimitSlack)) {
        violation(line_no, fmt::format("rotary feed {:.4f} deg/min is above the maximum {} deg/min", rot_speed,
                                       m.feed.rotary_max_deg_min));
      }
    }

    const int pieces = 1 + static_cast<int>(std::ceil(std::max(d_tilt, d_c) / kLengthStepDeg));
    Vec3 last_tip = motion::forward(m, pos).tip_part_mm;
    double length = 0.0;
    for (int k = 1; k <= pieces; ++k) {
      const Vec3 tip = motion::forward(m, lerp(pos, target, static_cast<double>(k) / pieces)).tip_part_mm;
      length += norm(tip - last_tip);
      last_tip = tip;
    }
    rep.path_length_mm += length;
    if (process_on) rep.deposit_length_mm += length;
    for (const double u : {0.25, 0.5, 0.75}) sample(line_no, lerp(pos, target, u));
    sample(line_no, target);
    pos = target;
  }
  return rep;
}

}  // namespace polyaxis::machine
