// What every e2e plan test checks of a plan written by the CLI: the program read back through
// forward kinematics (readback.h) and LinuxCNC's rs274 reading the same axis words.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "support/cli.h"
#include "support/readback.h"
#include "support/toolpath_3mf_replay.h"

namespace polyaxis::test {

inline nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(slurp(p)); }

inline std::string rs274_path() {
  for (const char* p : {"/usr/bin/rs274", "/usr/local/bin/rs274"}) {
    if (std::filesystem::exists(p)) return p;
  }
  return {};
}

// The shell command running RS274 on IN, writing the canonical calls to OUT, with HOME set to OUT's
// directory: rs274 keeps its tool table in $HOME/.tool.mmap, opened with O_TRUNC and mapped, so
// two runs sharing a HOME truncate each other's mapping and one dies of SIGBUS (seen in parallel
// ctest runs, about one concurrent run in six).
inline std::string rs274_command(const std::string& rs274, const std::filesystem::path& in, const std::filesystem::path& out) {
  return "HOME='" + out.parent_path().string() + "' '" + rs274 + "' -g '" + in.string() + "' '" + out.string() + "'";
}

// The axis words of every G0/G1 block in OUR file, in order, carried forward like a controller.
inline std::vector<std::array<double, 6>> our_positions(const std::string& gcode) {
  std::vector<std::array<double, 6>> out;
  std::array<double, 6> pos{0, 0, 0, 0, 0, 0};
  std::istringstream in(gcode);
  std::string line;
  const std::string letters = "XYZABC";
  static const std::regex kMove("\\bG[01]\\b|^G[01] |^G0|^G1");  // built once: a million-line program is read here
  while (std::getline(in, line)) {
    const auto paren = line.find('(');
    if (paren != std::string::npos) line = line.substr(0, paren);
    if (!std::regex_search(line, kMove)) continue;
    bool moved = false;
    for (std::size_t i = 0; i < 6; ++i) {
      const auto at = line.find(letters[i]);
      if (at == std::string::npos) continue;
      pos[i] = std::stod(line.substr(at + 1));
      moved = true;
    }
    if (moved) out.push_back(pos);
  }
  return out;
}

// rs274's canonical STRAIGHT_FEED / STRAIGHT_TRAVERSE positions (x y z a b c).
inline std::vector<std::array<double, 6>> rs274_positions(const std::string& canon) {
  std::vector<std::array<double, 6>> out;
  const std::regex call("(STRAIGHT_FEED|STRAIGHT_TRAVERSE)\\(([^)]*)\\)");
  for (auto it = std::sregex_iterator(canon.begin(), canon.end(), call); it != std::sregex_iterator(); ++it) {
    std::stringstream s((*it)[2].str());
    std::array<double, 6> p{};
    std::string item;
    for (std::size_t i = 0; i < 6 && std::getline(s, item, ','); ++i) p[i] = std::stod(item);
    out.push_back(p);
  }
  return out;
}

// Points on the surface of MESH at most MAX_EDGE_MM apart: its triangles split in four until no
// edge is longer (the test's own sampling, apart from the library's).
inline std::vector<core::Vec3> surface_points(const io::RawMesh& mesh, double max_edge_mm) {
  std::vector<core::Vec3> out;
  std::vector<std::array<core::Vec3, 3>> todo;
  for (const auto& t : mesh.triangles) todo.push_back({mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]});
  while (!todo.empty()) {
    const auto [a, b, c] = todo.back();
    todo.pop_back();
    if (std::max({core::norm(b - a), core::norm(c - b), core::norm(a - c)}) <= max_edge_mm) {
      out.push_back(a), out.push_back(b), out.push_back(c), out.push_back((a + b + c) / 3.0);
      continue;
    }
    const core::Vec3 ab = (a + b) * 0.5, bc = (b + c) * 0.5, ca = (c + a) * 0.5;
    todo.push_back({a, ab, ca}), todo.push_back({ab, b, bc}), todo.push_back({ca, bc, c}), todo.push_back({ab, bc, ca});
  }
  return out;
}

// MESH (the part's frame) placed as plan.json's placement says: rows · p + translation.
inline io::RawMesh placed(io::RawMesh mesh, const nlohmann::json& plan) {
  const auto& rows = plan["placement_rotation"];
  const auto& t = plan["placement_mm"];
  for (core::Vec3& p : mesh.points) {
    const core::Vec3 q = p;
    for (int i = 0; i < 3; ++i) {
      p[i] = rows[i][0].get<double>() * q.x + rows[i][1].get<double>() * q.y + rows[i][2].get<double>() * q.z + t[i].get<double>();
    }
  }
  return mesh;
}

struct Tip {
  int layer = -1;
  core::Vec3 tip;
  core::Vec3 axis;  // the tool axis, unit, up the nozzle
  int region = -1;
};

// The end points of the process-on feed blocks of the program in DIR, through forward kinematics on
// the default machine, with their "(layer N region R" comment.
inline std::vector<Tip> deposit_tips(const std::filesystem::path& dir, const std::string& name) {
  auto m = machine::parse_machine(machine::default_machine_json(), "default");
  auto p = process::parse_process(process::default_process_json(), "default");
  EXPECT_TRUE(m.ok() && p.ok());
  std::istringstream in(slurp(dir / (name + ".ngc")));
  std::string line;
  std::array<double, 6> pos{};
  bool on = false;
  int layer = -1, region = -1;
  std::vector<Tip> out;
  const std::string letters = "XYZABC";
  while (std::getline(in, line)) {
    if (line.rfind("(layer ", 0) == 0) {
      layer = std::stoi(line.substr(7));
      const auto at = line.find(" region ");
      region = at == std::string::npos ? -1 : std::stoi(line.substr(at + 8));
    }
    if (line == p.value().process_on) on = true;
    if (line == p.value().process_off) on = false;
    if (line.rfind("G1 ", 0) != 0) continue;
    for (std::size_t i = 0; i < 6; ++i) {
      if (const auto at = line.find(letters[i]); at != std::string::npos) pos[i] = std::stod(line.substr(at + 1));
    }
    if (!on) continue;
    const auto f = machine::forward(m.value(), {pos[0], pos[1], pos[2], pos[3], pos[5]});
    out.push_back({layer, f.tip_part_mm, f.tool_axis_part, region});
  }
  return out;
}

// How far MESH's surface lies from P along −N (unit), the nearest hit of that ray (+inf when none).
inline double depth_under(const io::RawMesh& mesh, core::Vec3 p, core::Vec3 n) {
  double best = INFINITY;
  for (const auto& t : mesh.triangles) {
    const core::Vec3 a = mesh.points[t[0]], b = mesh.points[t[1]], c = mesh.points[t[2]];
    // Möller–Trumbore with the ray p − s·n, s ≥ 0.
    const core::Vec3 dir = n * -1.0, e1 = b - a, e2 = c - a, q = core::cross(dir, e2);
    const double det = core::dot(e1, q);
    if (std::abs(det) < 1e-12) continue;
    const core::Vec3 r = p - a;
    const double u = core::dot(r, q) / det;
    const core::Vec3 w = core::cross(r, e1);
    const double v = core::dot(dir, w) / det;
    if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
    const double s = core::dot(e2, w) / det;
    if (s >= 0.0) best = std::min(best, s);
  }
  return best;
}

// The thickness of the beads of a program (deposit_tips), measured along each deposit point's tool
// axis: for a region's first layer to ON_TABLE, the part it is laid onto (twice the depth: the tip
// is on the layer's mid-surface), else to the beads of the region's layer before whose line passes
// within half a bead of the axis. The least and largest values and how many points were measured.
struct Thickness {
  double least = INFINITY, most = 0.0;
  std::size_t measured = 0, points = 0;
};
inline Thickness bead_thickness(const std::vector<Tip>& tips, const io::RawMesh& on_table, double bead_mm) {
  Thickness out;
  std::map<int, std::map<std::array<long, 3>, std::vector<core::Vec3>>> by_layer;  // 2-bead cells
  std::map<int, int> before;                                                     // layer -> its region's layer before (-1: first)
  std::map<int, int> last_of_region;
  const double cell = 2.0 * bead_mm;
  auto key = [&](core::Vec3 p) {
    return std::array<long, 3>{static_cast<long>(std::floor(p.x / cell)), static_cast<long>(std::floor(p.y / cell)), static_cast<long>(std::floor(p.z / cell))};
  };
  for (const Tip& t : tips) {
    by_layer[t.layer][key(t.tip)].push_back(t.tip);
    if (!before.count(t.layer)) {
      const auto last = last_of_region.find(t.region);
      before[t.layer] = last == last_of_region.end() ? -1 : last->second;
      last_of_region[t.region] = t.layer;
    }
  }
  for (const Tip& t : tips) {
    ++out.points;
    double thickness = NAN;
    if (before[t.layer] < 0) {
      thickness = 2.0 * depth_under(on_table, t.tip, t.axis);
    } else {
      const auto& below = by_layer[before[t.layer]];
      double best = 0.5 * bead_mm;
      const auto k = key(t.tip);
      for (long i = -1; i <= 1; ++i)
        for (long j = -1; j <= 1; ++j)
          for (long l = -1; l <= 1; ++l) {
            const auto it = below.find({k[0] + i, k[1] + j, k[2] + l});
            if (it == below.end()) continue;
            for (const core::Vec3& q : it->second) {
              const double along = core::dot(t.tip - q, t.axis), across = core::norm((t.tip - q) - t.axis * along);
              if (across < best) best = across, thickness = along;
            }
          }
    }
    if (std::isnan(thickness) || !std::isfinite(thickness)) continue;
    ++out.measured;
    out.least = std::min(out.least, thickness), out.most = std::max(out.most, thickness);
  }
  return out;
}

// The program in DIR read back (support/readback.h) on the default machine and process, with the
// plate report.json states; checks what every plan must hold and returns the reading.
// ALLOW_COLLISIONS: a plan written with --allow-collisions, whose collisions are listed.
// PREBUILT: a part already on the table, in the table frame (placed(): a --substrate mesh placed as
// plan.json says): the deposit may rest on it and the head must keep out of it.
inline ReadBack check_readback(const std::filesystem::path& dir, const std::string& name, bool allow_collisions = false,
                               const io::RawMesh* prebuilt = nullptr, const std::filesystem::path& machine_file = {}) {
  auto machine = machine_file.empty() ? machine::parse_machine(machine::default_machine_json(), "default")
                                      : machine::parse_machine(slurp(machine_file), machine_file.string());
  auto process = process::parse_process(process::default_process_json(), "default");
  EXPECT_TRUE(machine.ok() && process.ok());
  const auto report = read_json(dir / "report.json");
  const auto& sub = report["substrate"];
  Plate plate{sub["x_mm"][0].get<double>(), sub["x_mm"][1].get<double>(), sub["y_mm"][0].get<double>(), sub["y_mm"][1].get<double>(),
              sub["top_z_mm"].get<double>(), sub["top_z_mm"].get<double>() - sub["thickness_mm"].get<double>()};
  if (std::filesystem::exists(dir / "plan.json")) {
    const auto head = read_json(dir / "plan.json")["head"];
    if (head.contains("table_radius_mm")) {
      plate.table_radius = head["table_radius_mm"].get<double>();
      plate.table_cx = head["table_centre_mm"][0].get<double>(), plate.table_cy = head["table_centre_mm"][1].get<double>();
    }
  }
  const process::ProcessConfig& p = process.value();
  const double spacing = p.bead_width_mm / 4.0;
  const double step = std::max(p.max_step_bead_share * p.bead_width_mm, p.layer_max_mm * std::tan(p.self_supporting_deg * M_PI / 180.0));
  const double reach = std::hypot(std::max(p.layer_max_mm, 0.5 * (p.layer_max_mm + p.bead_width_mm)), std::max(0.5 * p.bead_width_mm, step)) + spacing;
  std::vector<core::Vec3> ground, solid;
  if (prebuilt != nullptr) {
    ground = surface_points(*prebuilt, 0.5 * reach);
    solid = surface_points(*prebuilt, 2.0 * p.bead_width_mm);
  }
  const std::string program = name + std::string(machine::program_extension(machine.value().post));
  std::string text = slurp(dir / program);
  machine::MachineConfig reader = machine.value();
  if (reader.post == machine::PostDialect::k3mfToolpath) {
    // The tests' own reading of the package, as the TRAORI blocks it amounts to.
    text = replay_toolpath_3mf(text, p).traori;
    reader.post = machine::PostDialect::kSiemensTraori;
  }
  const ReadBack rb = read_back(reader, p, plate, text, reach, spacing, false, ground, solid);
  if (!allow_collisions) {
    EXPECT_EQ(rb.head_in_prebuilt, 0u) << name << ": " << rb.first_problem;
  }
  EXPECT_GT(rb.deposit_samples, 0u) << name;
  EXPECT_EQ(rb.head_below, 0u) << name << ": " << rb.worst_head_mm << " mm; " << rb.first_problem;
  EXPECT_LE(rb.slow_s, 0.01 * rb.on_s) << name;
  EXPECT_TRUE(rb.regions_starting_in_air.empty()) << name << ": " << rb.first_problem;
  if (report["support_free"].get<bool>()) {
    EXPECT_EQ(rb.ungrounded, 0u) << name << ": " << rb.first_problem;
  }
  // The library's own verification of the same program agrees, and finds the head clear of the
  // deposit everywhere (a plan with collisions is refused unless --allow-collisions).
  if (!allow_collisions) {
    EXPECT_EQ(report["collisions"].get<int>(), 0) << name << report["collision_list"];
  }
  const auto& check = report["build_check"];
  EXPECT_EQ(check["head_collisions"].get<int>(), 0) << name;
  EXPECT_TRUE(check["mid_air_regions"].empty()) << name;
  EXPECT_LE(check["stalled_s"].get<double>(), 0.01 * check["process_on_s"].get<double>()) << name;
  if (report["support_free"].get<bool>()) {
    EXPECT_EQ(check["ungrounded_samples"].get<int>(), 0) << name << check["problems"];
  }
  return rb;
}

// rs274 accepts the program NGC (in DIR) and reads the same axis positions as its words say, to
// 1 µm / 0.001°; skipped (false) when rs274 is not installed.
inline bool expect_rs274_reads(const std::filesystem::path& dir, const std::filesystem::path& ngc) {
  const std::string rs274 = rs274_path();
  if (rs274.empty()) return false;
  const auto canon = dir / "canon.txt";
  const int status = std::system((rs274_command(rs274, ngc, canon) + " >/dev/null 2>&1 </dev/null").c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rs274 refused " << ngc;
  const auto theirs = rs274_positions(slurp(canon));
  const auto ours = our_positions(slurp(ngc));
  EXPECT_FALSE(theirs.empty());
  EXPECT_EQ(theirs.size(), ours.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(ours.size(), theirs.size()); ++i) {
    for (std::size_t k = 0; k < 6; ++k) worst = std::max(worst, std::fabs(ours[i][k] - theirs[i][k]));
  }
  EXPECT_LE(worst, 1e-3) << "rs274 reads different positions";
  return true;
}

}  // namespace polyaxis::test
