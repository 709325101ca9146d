// The e2e tests' own reading of a program as the machine runs it, written apart from the
// library's verifier (verify/verify.h) so the two check each other: the axis words of every
// block, joint-linear between blocks, through forward kinematics (machine::forward, itself checked
// against LinuxCNC's trt-kins), sampled; the head, the grounding of every bead and the stalls
// checked with rules stated here.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::test {

struct Plate {  // the substrate's rectangle and top, and the table's top (report.json "substrate")
  double x0, x1, y0, y1, top, table_top;
  // The table is a disc (plan.json "head": table_radius_mm about table_centre_mm); beyond its edge
  // the build model holds nothing (the machine file describes no cradle under it).
  double table_radius = INFINITY, table_cx = 0.0, table_cy = 0.0;
};

struct ReadBack {
  std::size_t samples = 0, deposit_samples = 0;
  std::size_t head_below = 0;       // samples with a head point below the plate's or the table's top
  double worst_head_mm = 0.0;
  std::size_t ungrounded = 0;       // deposit samples with no earlier-layer deposit (or plate) near under them
  std::vector<int> regions_starting_in_air;
  double on_s = 0.0, slow_s = 0.0;  // process-on feed time, and of it with the tip below half the deposit feed
  std::size_t head_in_deposit = 0;  // samples with earlier deposit in the head (only when asked: brute force)
  std::size_t head_in_prebuilt = 0; // samples with the prebuilt part in the head (when given)
  std::string first_problem;
};

// Reads GCODE on MACHINE. Rules:
// - head: the nozzle is a cone (half-angle θ, height z1) under a cylinder (radius R, height H);
//   every circle bounding them (at z1 with the larger radius, at z1 + H with R) has its lowest
//   point at centre.z − r·sin(tilt); that point, and the tip, must not be below the plate's top
//   where the circle's disc overlaps the plate, nor below the table's top elsewhere over the
//   table's disc (PLATE.table_radius; beyond it the build model holds nothing). Where that fails,
//   the head's lines every degree about the axis decide instead (the cone's side from 1 mm above
//   the tip, the cylinder's bottom and side): no part of a line over the plate's rectangle below
//   its top, no part of a line over the table's disc below the table's top.
// - grounding: a deposit sample is grounded when it is over the plate within REACH_MM of its top,
//   or when a deposit sample of an earlier layer ("(layer N" comments) lies within REACH_MM.
// - stall: a block with the process on whose tip path over its duration (F as LinuxCNC reads it
//   in G94: XYZ mm/min, else rotary deg/min) is below half the deposit feed.
// - a prebuilt part (PREBUILT: points on its surface, at most half of REACH_MM apart) grounds the
//   deposit as earlier layers do; and the head must hold none of HEAD_PREBUILT (points on its surface,
//   any spacing: the test's resolution), by the head rule below with no tip zone left out beyond
//   1.5 beads, checked every 3 beads of tip travel, every 2° of the tool axis's turn, and where
//   each block with the process off ends.
// - with HEAD_VS_DEPOSIT (small programs only: every sample against every earlier deposit sample),
//   a sample's head holds earlier deposit when a deposit sample farther than 1.5 beads from the tip
//   lies within half a bead of the cone's or the cylinder's side or end (each solid grown by half a
//   bead along its own height and radius).
inline ReadBack read_back(const machine::MachineConfig& m, const process::ProcessConfig& proc, const Plate& plate, const std::string& gcode,
                          double reach_mm, double spacing_mm, bool head_vs_deposit = false, const std::vector<core::Vec3>& prebuilt = {},
                          const std::vector<core::Vec3>& head_prebuilt = {}) {
  ReadBack rb;
  const double kPi = 3.14159265358979323846;
  const double z1 = m.nozzle.cone_height_mm, R = m.nozzle.cylinder_radius_mm, H = m.nozzle.cylinder_height_mm;
  const double r1 = std::max(R, z1 * std::tan(m.nozzle.tip_half_angle_deg * kPi / 180.0));
  auto surface = [&](double x, double y, double r) {
    const double dx = std::max({plate.x0 - x, 0.0, x - plate.x1}), dy = std::max({plate.y0 - y, 0.0, y - plate.y1});
    if (dx * dx + dy * dy <= r * r) return plate.top;
    return std::hypot(x - plate.table_cx, y - plate.table_cy) <= plate.table_radius + r ? plate.table_top : -INFINITY;
  };
  // Where a circle's disc overlaps the plate only in part, its part beyond the plate may be lower
  // than the plate's top: the head is taken by its lines instead, every degree about the axis (the
  // cone's side from the tip, the cylinder's bottom from the cone out, the cylinder's side), each
  // line's part over the plate against the plate's top and all of it against the table's.
  auto head_low_by_lines = [&](core::Vec3 t, core::Vec3 a) {
    const core::Vec3 u = core::normalized(core::cross(a, std::abs(a.z) < 0.9 ? core::Vec3{0, 0, 1} : core::Vec3{1, 0, 0}));
    const core::Vec3 v = core::cross(a, u);
    const double rc = z1 * std::tan(m.nozzle.tip_half_angle_deg * kPi / 180.0);
    double low = INFINITY;
    auto line = [&](core::Vec3 p, core::Vec3 q) {
      {  // the part of P→Q over the table's disc against its top
        double s0 = 0.0, s1 = 1.0;
        if (std::isfinite(plate.table_radius)) {
          const double ex = q.x - p.x, ey = q.y - p.y, fx = p.x - plate.table_cx, fy = p.y - plate.table_cy;
          const double qa = ex * ex + ey * ey, qb = 2.0 * (ex * fx + ey * fy), qc = fx * fx + fy * fy - plate.table_radius * plate.table_radius;
          if (qa < 1e-18) {
            if (qc > 0.0) s1 = -1.0;
          } else {
            const double disc = qb * qb - 4.0 * qa * qc;
            if (disc < 0.0) {
              s1 = -1.0;
            } else {
              s0 = std::max(0.0, (-qb - std::sqrt(disc)) / (2.0 * qa)), s1 = std::min(1.0, (-qb + std::sqrt(disc)) / (2.0 * qa));
            }
          }
        }
        if (s0 <= s1) low = std::min(low, std::min(p.z + (q.z - p.z) * s0, p.z + (q.z - p.z) * s1) - plate.table_top);
      }
      // The part of P→Q over the plate's rectangle (Liang–Barsky), its lower end against the top.
      double t0 = 0.0, t1 = 1.0;
      const double d[2] = {q.x - p.x, q.y - p.y}, lo[2] = {plate.x0 - p.x, plate.y0 - p.y}, hi[2] = {plate.x1 - p.x, plate.y1 - p.y};
      for (int i = 0; i < 2 && t0 <= t1; ++i) {
        if (std::abs(d[i]) < 1e-12) {
          if (lo[i] > 0.0 || hi[i] < 0.0) t1 = -1.0;
          continue;
        }
        const double ta = lo[i] / d[i], tb = hi[i] / d[i];
        t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
      }
      if (t0 <= t1) low = std::min(low, std::min(p.z + (q.z - p.z) * t0, p.z + (q.z - p.z) * t1) - plate.top);
    };
    for (int deg = 0; deg < 360; ++deg) {
      const core::Vec3 w = u * std::cos(deg * kPi / 180.0) + v * std::sin(deg * kPi / 180.0);
      line(t + a * 1.0 + w * (rc / z1), t + a * z1 + w * rc);
      line(t + a * z1 + w * rc, t + a * z1 + w * R);
      line(t + a * z1 + w * R, t + a * (z1 + H) + w * R);
    }
    return low;
  };
  std::vector<core::Vec3> all_deposit;  // every deposit sample so far (HEAD_VS_DEPOSIT)
  std::map<std::array<long, 3>, std::vector<core::Vec3>> earlier;  // deposit of finished layers, 1-reach cells
  std::vector<core::Vec3> layer_pts;
  auto cell = [&](core::Vec3 p) {
    return std::array<long, 3>{static_cast<long>(std::floor(p.x / reach_mm)), static_cast<long>(std::floor(p.y / reach_mm)),
                               static_cast<long>(std::floor(p.z / reach_mm))};
  };
  auto near_earlier = [&](core::Vec3 p) {
    const auto c = cell(p);
    for (long i = -1; i <= 1; ++i)
      for (long j = -1; j <= 1; ++j)
        for (long k = -1; k <= 1; ++k) {
          const auto it = earlier.find({c[0] + i, c[1] + j, c[2] + k});
          if (it == earlier.end()) continue;
          for (const core::Vec3& q : it->second)
            if (core::norm(q - p) <= reach_mm) return true;
        }
    return false;
  };
  for (const core::Vec3& p : prebuilt) earlier[cell(p)].push_back(p);
  // A head sample holds Q when Q, farther than 1.5 beads from the tip, lies within half a bead of
  // the cone's or the cylinder's side or end.
  const double grow = 0.5 * proc.bead_width_mm, ignore = 1.5 * proc.bead_width_mm;
  const double cos_th = std::cos(m.nozzle.tip_half_angle_deg * kPi / 180.0), sin_th = std::sin(m.nozzle.tip_half_angle_deg * kPi / 180.0);
  // Q within GROWN of the cone or the cylinder (each bound is 1-Lipschitz in Q, so a ball of radius
  // s round Q can reach them only where Q is within GROWN + s).
  auto near_head = [&](core::Vec3 t, core::Vec3 a, core::Vec3 q, double grown) {
    const core::Vec3 d = q - t;
    const double h = core::dot(d, a);
    if (h < -grown || h > z1 + H + grown) return false;
    const double r = core::norm(d - a * h);
    const bool in_cone = h <= z1 + grown && r * cos_th - h * sin_th <= grown;
    const bool in_cylinder = h >= z1 - grown && r <= R + grown;
    return in_cone || in_cylinder;
  };
  auto in_head = [&](core::Vec3 t, core::Vec3 a, core::Vec3 q) { return core::norm(q - t) > ignore && near_head(t, a, q, grow); };
  // HEAD_PREBUILT in cubic cells: a check visits only the cells whose centre lies within half a
  // cell's diagonal of the grown head (the cone near the tip, where the deposit lies on the
  // prebuilt part, is far narrower than the cylinder above it).
  const double prebuilt_cell = 4.0;
  std::map<std::array<long, 3>, std::vector<core::Vec3>> prebuilt_cells;
  for (const core::Vec3& q : head_prebuilt) {
    prebuilt_cells[{static_cast<long>(std::floor(q.x / prebuilt_cell)), static_cast<long>(std::floor(q.y / prebuilt_cell)),
                    static_cast<long>(std::floor(q.z / prebuilt_cell))}].push_back(q);
  }
  std::vector<std::pair<core::Vec3, const std::vector<core::Vec3>*>> prebuilt_by_cell;
  for (const auto& [c, pts] : prebuilt_cells) {
    auto mid = [&](long i) { return (static_cast<double>(i) + 0.5) * prebuilt_cell; };
    prebuilt_by_cell.emplace_back(core::Vec3{mid(c[0]), mid(c[1]), mid(c[2])}, &pts);
  }
  const double cell_grow = grow + 0.5 * std::sqrt(3.0) * prebuilt_cell;
  auto prebuilt_in_head = [&](core::Vec3 t, core::Vec3 a) {
    for (const auto& [centre, pts] : prebuilt_by_cell) {
      if (!near_head(t, a, centre, cell_grow)) continue;
      for (const core::Vec3& q : *pts) {
        if (in_head(t, a, q)) return true;
      }
    }
    return false;
  };
  double since_prebuilt_check = INFINITY;
  core::Vec3 last_checked, last_checked_axis{0, 0, 1};
  std::istringstream in(gcode);
  std::string line;
  std::array<double, 6> pos{}, prev{};
  bool have = false, on = false;
  int layer = -1, region = -1;
  double feed = 0.0;
  std::vector<int> started;
  const std::regex comment(R"(^(?:\(|; |\s*! )layer (\d+) region (\d+))");
  std::smatch mt;
  const std::string letters = "XYZABC";
  // Sinumerik TRAORI (machine "post" siemens-traori): X Y Z are the tip and A3= B3= C3= the tool
  // vector, both in the part frame: no kinematics between them and the head. Between blocks the tip
  // moves straight and the vector turns along the great circle (here its normalised chord, within
  // a few micrometres at the head's sample spacing).
  // ABB RAPID (post abb-rapid): each move's robtarget gives the tip and the TCP's quaternion in the
  // part frame (the tool axis is its −z), v_tcp the tip's speed (mm/s); SetDO on the process file's
  // signal, or ArcLStart (off on the way, on after) ArcL ArcLEnd (on, off after), switch the
  // process. Read like TRAORI's blocks from there on; a MoveJ as a rapid.
  // ISO under G43.4 (post iso-tcp): X Y Z are the tip in the part frame and A/B C the rotary axes,
  // which turn linearly while the tip runs straight; the tool axis is the rotary axes' (forward
  // kinematics of the interpolated angles).
  const bool rapid_module = m.post == machine::PostDialect::kAbbRapid;
  const bool traori = m.post == machine::PostDialect::kSiemensTraori || rapid_module;
  const bool tcp = m.post == machine::PostDialect::kIsoTcp;
  const std::regex rapid_move(R"(^\s*(MoveJ|MoveL|ArcLStart|ArcLEnd|ArcL) \[\[([^,]+),([^,]+),([^\]]+)\],\[([^,]+),([^,]+),([^,]+),([^\]]+)\],.*?\]\],\[([^,]+),)");
  std::array<double, 3> vec{0.0, 0.0, 1.0}, prev_vec = vec;
  while (std::getline(in, line)) {
    if (rapid_module) {
      if (line.find("SetDO " + proc.rapid.signal + ",1;") != std::string::npos) on = true;
      if (line.find("SetDO " + proc.rapid.signal + ",0;") != std::string::npos) on = false;
      std::smatch rm;
      if (!std::regex_search(line, rm, rapid_move)) {
        if (!std::regex_search(line, mt, comment)) continue;
      } else {
        const std::string instr = rm[1];
        const double w = std::stod(rm[5]), x = std::stod(rm[6]), y = std::stod(rm[7]), z = std::stod(rm[8]);
        const double n2 = w * w + x * x + y * y + z * z;
        // −z of the quaternion's frame, written as a TRAORI block for the reading below.
        const double vx = -2.0 * (x * z + w * y) / n2, vy = -2.0 * (y * z - w * x) / n2, vz = -(1.0 - 2.0 * (x * x + y * y) / n2);
        if (proc.rapid.arc) on = instr == "ArcL" || instr == "ArcLEnd";
        line = (instr == "MoveJ" ? "G0 X" : "G1 X") + std::string(rm[2]) + " Y" + std::string(rm[3]) + " Z" + std::string(rm[4]) +
               " A3=" + std::to_string(vx) + " B3=" + std::to_string(vy) + " C3=" + std::to_string(vz) + " F" +
               std::to_string(60.0 * std::stod(rm[9]));
      }
    }
    if (std::regex_search(line, mt, comment)) {
      const int l = std::stoi(mt[1]);
      if (l != layer) {
        for (const core::Vec3& p : layer_pts) earlier[cell(p)].push_back(p);
        layer_pts.clear();
      }
      layer = l, region = std::stoi(mt[2]);
      continue;
    }
    if (line == proc.process_on && !rapid_module) on = true;
    if (line == proc.process_off && !rapid_module) on = false;
    if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
    const bool rapid = line[1] == '0';
    prev = pos;
    prev_vec = vec;
    for (std::size_t i = 0; i < (traori ? 3u : 6u); ++i) {
      const auto at = line.find(letters[i]);
      if (at != std::string::npos) pos[i] = std::stod(line.substr(at + 1));
    }
    if (traori) {
      for (std::size_t i = 0; i < 3; ++i) {
        const auto at = line.find(std::string(1, "ABC"[i]) + "3=");
        if (at != std::string::npos) vec[i] = std::stod(line.substr(at + 3));
      }
    }
    if (const auto f = line.find('F'); f != std::string::npos) feed = std::stod(line.substr(f + 1));
    const char tilt = machine::tilt_axis_letter(m.kind);
    auto pose = [&](const std::array<double, 6>& a, const std::array<double, 6>& b, double u) {
      auto lerp = [&](std::size_t i) { return a[i] + (b[i] - a[i]) * u; };
      return machine::MachinePose{lerp(0), lerp(1), lerp(2), tilt == 'B' ? lerp(4) : lerp(3), lerp(5)};
    };
    auto tool = [&](double u) {
      if (tcp) {
        machine::MachinePose angles = pose(prev, pos, u);
        const core::Vec3 tip{angles.x_mm, angles.y_mm, angles.z_mm};
        angles.x_mm = angles.y_mm = angles.z_mm = 0.0;
        return machine::MachineToolPose{tip, machine::forward(m, angles).tool_axis_part};
      }
      if (!traori) return machine::forward(m, pose(prev, pos, u));
      const core::Vec3 a{prev_vec[0], prev_vec[1], prev_vec[2]}, b{vec[0], vec[1], vec[2]};
      const core::Vec3 t{prev[0] + (pos[0] - prev[0]) * u, prev[1] + (pos[1] - prev[1]) * u, prev[2] + (pos[2] - prev[2]) * u};
      return machine::MachineToolPose{t, core::normalized(a * (1.0 - u) + b * u)};
    };
    const core::Vec3 from = tool(0.0).tip_part_mm;
    const core::Vec3 to = tool(1.0).tip_part_mm;
    const double turn_deg = std::acos(std::clamp(core::dot(core::normalized(core::Vec3{prev_vec[0], prev_vec[1], prev_vec[2]}),
                                                           core::normalized(core::Vec3{vec[0], vec[1], vec[2]})),
                                                 -1.0, 1.0)) * 180.0 / kPi;
    const double rot = traori ? turn_deg : std::max({std::abs(pos[3] - prev[3]), std::abs(pos[4] - prev[4]), std::abs(pos[5] - prev[5])});
    const int n = have ? std::max(1, static_cast<int>(std::ceil(std::max(core::norm(to - from) / spacing_mm, rot)))) : 1;
    double length = 0.0;
    core::Vec3 last = from;
    for (int k = have ? 1 : n; k <= n; ++k) {
      const machine::MachineToolPose tp = tool(static_cast<double>(k) / n);
      const core::Vec3 t = tp.tip_part_mm, a = core::normalized(tp.tool_axis_part);
      length += core::norm(t - last);
      last = t;
      ++rb.samples;
      const double side = std::sqrt(std::max(0.0, 1.0 - a.z * a.z));
      double low = t.z - surface(t.x, t.y, 0.0);
      for (const auto& [s, r] : {std::pair<double, double>{z1, r1}, {z1 + H, R}}) {
        const core::Vec3 c = t + a * s;
        low = std::min(low, c.z - r * side - surface(c.x, c.y, r));
      }
      if (low < -1e-3) low = std::min(t.z - surface(t.x, t.y, 0.0), head_low_by_lines(t, a));
      if (low < -1e-3) {
        ++rb.head_below;
        rb.worst_head_mm = std::max(rb.worst_head_mm, -low);
        if (rb.first_problem.empty()) rb.first_problem = "head below the plate or table: " + line;
      }
      if (head_vs_deposit) {
        for (const core::Vec3& q : all_deposit) {
          if (in_head(t, a, q)) {
            ++rb.head_in_deposit;
            if (rb.first_problem.empty()) rb.first_problem = "head in earlier deposit: " + line;
            break;
          }
        }
      }
      since_prebuilt_check += core::norm(t - last_checked);
      last_checked = t;
      // Deposit blocks are checked every 3 beads of tip travel or 2° of turn; the others also
      // where they end (retracts, approaches and transits are few and long).
      const bool turned = core::dot(a, last_checked_axis) < std::cos(2.0 * kPi / 180.0);
      if (!head_prebuilt.empty() && (since_prebuilt_check >= 3.0 * proc.bead_width_mm || turned || (k == n && !on))) {
        since_prebuilt_check = 0.0;
        last_checked_axis = a;
        if (prebuilt_in_head(t, a)) {
          ++rb.head_in_prebuilt;
          if (rb.first_problem.empty()) rb.first_problem = "head in the prebuilt part: " + line;
        }
      }
      if (!on || !have) continue;
      ++rb.deposit_samples;
      if (head_vs_deposit) all_deposit.push_back(t);
      const bool first = std::find(started.begin(), started.end(), region) == started.end();
      if (first) started.push_back(region);
      const bool on_plate = t.x >= plate.x0 && t.x <= plate.x1 && t.y >= plate.y0 && t.y <= plate.y1 && t.z >= plate.top - 1e-3 &&
                            t.z <= plate.top + reach_mm;
      if (!on_plate && !near_earlier(t)) {
        ++rb.ungrounded;
        if (first) rb.regions_starting_in_air.push_back(region);
        if (rb.first_problem.empty()) rb.first_problem = "bead over nothing: " + line;
      }
      layer_pts.push_back(t);
    }
    if (have && on && !rapid && feed > 0.0) {
      const double xyz = std::hypot(pos[0] - prev[0], pos[1] - prev[1], pos[2] - prev[2]);  // the tip's under TRAORI
      const double rot_len = traori ? turn_deg : std::hypot(pos[3] - prev[3], pos[4] - prev[4], pos[5] - prev[5]);
      const double minutes = xyz > 0.0 ? xyz / feed : rot_len / feed;
      const double seconds = minutes * 60.0;
      rb.on_s += seconds;
      if (seconds > 0.0 && length / seconds < 0.5 * proc.deposit_feed_mm_s) rb.slow_s += seconds;
    }
    have = true;
  }
  return rb;
}

}  // namespace polyaxis::test
