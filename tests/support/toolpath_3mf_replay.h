// The tests' own reading of a 3MF toolpath package (post/toolpath_3mf.h), written apart from the
// library's reader (verify/toolpath_3mf_walk.cpp): the parts taken out of the zip, every pose read
// with a regular expression, the frame's local z computed here from the quaternion, and the whole
// written out as TRAORI blocks (the tip and the tool vector in the part frame, "; layer N region R"
// comments, the process file's codes) for read_back (readback.h) to check as it checks TRAORI.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "polyaxis/io/zip_archive.h"
#include "polyaxis/process/process.h"

namespace polyaxis::test {

struct Replay3mf {
  std::string traori;               // the program as TRAORI blocks
  std::vector<core::Vec3> tips;     // every pose, in reading order (jumps and points)
  std::vector<core::Vec3> axes;
  std::size_t layers = 0, segments = 0, points = 0;
  double worst_quaternion_norm_error = 0.0;
};

inline std::map<std::string, std::string> zip_parts(const std::string& package) {
  auto entries = io::read_zip(package, "package", "a 3MF package", [](std::string_view) { return true; });
  EXPECT_TRUE(entries.ok()) << (entries.ok() ? "" : entries.error().message);
  std::map<std::string, std::string> out;
  if (entries.ok()) {
    for (auto& e : entries.value()) out[e.path] = e.bytes;
  }
  return out;
}

inline Replay3mf replay_toolpath_3mf(const std::string& package, const process::ProcessConfig& proc) {
  Replay3mf out;
  auto parts = zip_parts(package);
  const std::string& model = parts["3D/3dmodel.model"];
  std::smatch m;
  double unit = 0.0, speed = 0.0, fmin = 0.0, fmax = 0.0, wait_us = 0.0;
  if (std::regex_search(model, m, std::regex(R"~(unitfactor="([^"]+)")~"))) unit = std::stod(m[1]);
  if (std::regex_search(model, m, std::regex(R"~(depositionspeed="([^"]+)")~"))) speed = std::stod(m[1]);
  if (std::regex_search(model, m, std::regex(R"~(prewaittime="([^"]+)")~"))) wait_us = std::stod(m[1]);
  if (std::regex_search(model, m, std::regex(R"~(minvalue="([^"]+)" maxvalue="([^"]+)")~"))) fmin = std::stod(m[1]), fmax = std::stod(m[2]);
  EXPECT_GT(unit, 0.0);
  EXPECT_GT(speed, 0.0);
  const std::regex pose_re(R"r(<(point6d|pa:pose) x="(-?\d+)" y="(-?\d+)" z="(-?\d+)" i="([^"]+)" j="([^"]+)" k="([^"]+)" w="([^"]+)"(?: (speed|f)="([^"]+)")?/>)r");
  const std::regex layer_path(R"~(path="/(Toolpath/Layers/layer\d+\.xml)")~");
  std::string& t = out.traori;
  bool on = false;
  auto block = [&](const std::smatch& p, bool feed_move, double feed_mm_s) {
    const double i = std::stod(p[5]), j = std::stod(p[6]), k = std::stod(p[7]), w = std::stod(p[8]);
    const double n2 = i * i + j * j + k * k + w * w;
    out.worst_quaternion_norm_error = std::max(out.worst_quaternion_norm_error, std::abs(n2 - 1.0));
    // The local z: the rotation matrix's third column (2(ik + jw), 2(jk − iw), 1 − 2(i² + j²)) of the unit quaternion.
    const core::Vec3 z = core::normalized(core::Vec3{2.0 * (i * k + j * w) / n2, 2.0 * (j * k - i * w) / n2, 1.0 - 2.0 * (i * i + j * j) / n2});
    const core::Vec3 tip{std::stod(p[2]) * unit, std::stod(p[3]) * unit, std::stod(p[4]) * unit};
    out.tips.push_back(tip), out.axes.push_back(z);
    t += fmt::format("{} X{:.4f} Y{:.4f} Z{:.4f} A3={:.9f} B3={:.9f} C3={:.9f}", feed_move ? "G1" : "G0", tip.x, tip.y, tip.z, z.x, z.y, z.z);
    if (feed_move) t += fmt::format(" F{:.6f}", feed_mm_s * 60.0);
    t += '\n';
  };
  auto process = [&](bool want) {
    if (want == on) return;
    t += (want ? proc.process_on : proc.process_off) + "\n";
    on = want;
  };
  for (auto it = std::sregex_iterator(model.begin(), model.end(), layer_path); it != std::sregex_iterator(); ++it) {
    const std::string& layer = parts[(*it)[1]];
    ++out.layers;
    if (std::regex_search(layer, m, std::regex(R"~(<pa:layer index="(\d+)" region="(\d+)"/>)~"))) t += fmt::format("; layer {} region {}\n", m[1].str(), m[2].str());
    std::map<int, std::string> jumps;
    const std::regex jump_re(R"~(<pa:jump segment="(\d+)">(.*?)</pa:jump>)~");
    for (auto j = std::sregex_iterator(layer.begin(), layer.end(), jump_re); j != std::sregex_iterator(); ++j) jumps[std::stoi((*j)[1])] = (*j)[2];
    std::vector<std::string> segments;
    const std::regex seg_re(R"~(<segment type="polyline6d"[^>]*>([\s\S]*?)</segment>)~");
    for (auto s = std::sregex_iterator(layer.begin(), layer.end(), seg_re); s != std::sregex_iterator(); ++s) segments.push_back((*s)[1]);
    for (int s = 0; s <= static_cast<int>(segments.size()); ++s) {
      if (jumps.count(s) != 0) {
        process(false);
        const std::string& body = jumps[s];
        for (auto p = std::sregex_iterator(body.begin(), body.end(), pose_re); p != std::sregex_iterator(); ++p) {
          const bool has_speed = (*p)[9].matched;
          block(*p, has_speed, has_speed ? std::stod((*p)[10]) : 0.0);
        }
      }
      if (s == static_cast<int>(segments.size())) break;
      ++out.segments;
      const std::string& body = segments[static_cast<std::size_t>(s)];
      bool first = true;
      for (auto p = std::sregex_iterator(body.begin(), body.end(), pose_re); p != std::sregex_iterator(); ++p) {
        ++out.points;
        if (first) {
          process(false);
          block(*p, false, 0.0);
          process(true);
          if (wait_us > 0.0) t += fmt::format("G4 F{:.4f}\n", wait_us * 1e-6);
          first = false;
          continue;
        }
        const double f = (*p)[9].matched ? std::stod((*p)[10]) : 1.0;
        block(*p, true, (*p)[9].matched ? fmin + f * (fmax - fmin) : speed);
      }
    }
  }
  process(false);
  t += "M30\n";
  return out;
}

}  // namespace polyaxis::test
