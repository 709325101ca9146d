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
  // The tags "<NAME ..." in TEXT[from, to), one string each (std::regex is recursive: no long spans).
  auto tags = [](const std::string& text, std::size_t from, std::size_t to, const std::string& name) {
    std::vector<std::string> found;
    for (std::size_t at = text.find("<" + name + " ", from); at < to; at = text.find("<" + name + " ", at + 1)) {
      found.push_back(text.substr(at, text.find('>', at) + 1 - at));
    }
    return found;
  };
  auto attribute = [](const std::string& tag, const std::string& name) {
    const std::size_t at = tag.find(" " + name + "=\"");
    if (at == std::string::npos) return std::string();
    const std::size_t from = at + name.size() + 3;
    return tag.substr(from, tag.find('"', from) - from);
  };
  auto number = [](const std::string& text) { return text.empty() ? 0.0 : std::stod(text); };
  double unit = 0.0, speed = 0.0, fmin = 0.0, fmax = 0.0, wait_us = 0.0;
  for (const std::string& tag : tags(model, 0, model.size(), "tp:toolpathresource")) unit = number(attribute(tag, "unitfactor"));
  for (const std::string& tag : tags(model, 0, model.size(), "tp:toolpathprofile")) {
    speed = number(attribute(tag, "depositionspeed")), wait_us = number(attribute(tag, "prewaittime"));
  }
  for (const std::string& tag : tags(model, 0, model.size(), "tp:modifier")) fmin = number(attribute(tag, "minvalue")), fmax = number(attribute(tag, "maxvalue"));
  EXPECT_GT(unit, 0.0);
  EXPECT_GT(speed, 0.0);
  const std::regex pose_re(R"r(^<(point6d|pa:pose) x="(-?\d+)" y="(-?\d+)" z="(-?\d+)" i="([^"]+)" j="([^"]+)" k="([^"]+)" w="([^"]+)"(?: (speed|f)="([^"]+)")?/>)r");
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
  for (const std::string& entry : tags(model, 0, model.size(), "tp:toolpathlayer")) {
    const std::string& layer = parts[attribute(entry, "path").substr(1)];
    ++out.layers;
    for (const std::string& l : tags(layer, 0, layer.size(), "pa:layer")) {
      t += fmt::format("; layer {} region {}\n", attribute(l, "index"), attribute(l, "region"));
    }
    std::map<int, std::pair<std::size_t, std::size_t>> jumps;  // segment -> its pa:jump's span
    for (std::size_t at = layer.find("<pa:jump "); at != std::string::npos; at = layer.find("<pa:jump ", at + 1)) {
      jumps[std::stoi(attribute(layer.substr(at, layer.find('>', at) + 1 - at), "segment"))] = {at, layer.find("</pa:jump>", at)};
    }
    std::vector<std::pair<std::size_t, std::size_t>> segments;
    for (std::size_t at = layer.find("<segment type=\"polyline6d\""); at != std::string::npos; at = layer.find("<segment type=\"polyline6d\"", at + 1)) {
      segments.emplace_back(at, layer.find("</segment>", at));
    }
    for (int s = 0; s <= static_cast<int>(segments.size()); ++s) {
      if (jumps.count(s) != 0) {
        process(false);
        for (const std::string& tag : tags(layer, jumps[s].first, jumps[s].second, "pa:pose")) {
          std::smatch p;
          EXPECT_TRUE(std::regex_search(tag, p, pose_re)) << tag;
          const bool has_speed = p[9].matched;
          block(p, has_speed, has_speed ? std::stod(p[10]) : 0.0);
        }
      }
      if (s == static_cast<int>(segments.size())) break;
      ++out.segments;
      bool first = true;
      for (const std::string& tag : tags(layer, segments[static_cast<std::size_t>(s)].first, segments[static_cast<std::size_t>(s)].second, "point6d")) {
        std::smatch p;
        EXPECT_TRUE(std::regex_search(tag, p, pose_re)) << tag;
        ++out.points;
        if (first) {
          process(false);
          block(p, false, 0.0);
          process(true);
          if (wait_us > 0.0) t += fmt::format("G4 F{:.4f}\n", wait_us * 1e-6);
          first = false;
          continue;
        }
        const double f = p[9].matched ? std::stod(p[10]) : 1.0;
        block(p, true, p[9].matched ? fmin + f * (fmax - fmin) : speed);
      }
    }
  }
  process(false);
  t += "M30\n";
  return out;
}

}  // namespace polyaxis::test
