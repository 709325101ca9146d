// The tests' own reading of a waterjet program and of a part's sections, apart from the library:
// G-code blocks as the controller runs them (axis words, the jet's state from the process's codes,
// the "(layer N region R …)" comments), sections cut straight from the triangles, and exact-enough
// distances between rings.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::test {

struct P2 {
  double x, y;
};

inline double seg_point(P2 p, P2 a, P2 b) {
  const double ex = b.x - a.x, ey = b.y - a.y, l2 = ex * ex + ey * ey;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - a.x - t * ex, p.y - a.y - t * ey);
}

inline bool cross(P2 a, P2 b, P2 c, P2 d) {
  auto o = [](P2 p, P2 q, P2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
  return o(a, b, c) * o(a, b, d) < 0 && o(c, d, a) * o(c, d, b) < 0;
}

inline std::vector<P2> mm(const geom2d::Ring& r) {
  std::vector<P2> out;
  for (const auto& p : r) out.push_back({geom2d::to_mm(p.x), geom2d::to_mm(p.y)});
  return out;
}

inline bool inside(P2 p, const std::vector<P2>& ring) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    if ((ring[i].y > p.y) != (ring[j].y > p.y) && p.x < (ring[j].x - ring[i].x) * (p.y - ring[i].y) / (ring[j].y - ring[i].y) + ring[i].x) in = !in;
  }
  return in;
}

// The least distance between two rings that do not cross, or 0 when they cross or nest.
inline double ring_distance(const std::vector<P2>& a, const std::vector<P2>& b) {
  if (inside(a[0], b) || inside(b[0], a)) return 0.0;
  double d = INFINITY;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const P2 a0 = a[i], a1 = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < b.size(); ++j) {
      const P2 b0 = b[j], b1 = b[(j + 1) % b.size()];
      if (cross(a0, a1, b0, b1)) return 0.0;
      d = std::min({d, seg_point(a0, b0, b1), seg_point(a1, b0, b1), seg_point(b0, a0, a1), seg_point(b1, a0, a1)});
    }
  }
  return d;
}

// The part's section at height Z as segments, cut here from the triangles (apart from the library's
// slicing): the material of the sheet at that height.
inline std::vector<std::array<P2, 2>> section_segments(const mesh::Mesh& m, double z) {
  std::vector<std::array<P2, 2>> out;
  for (const auto& t : m.triangles) {
    std::vector<P2> hits;
    for (int e = 0; e < 3; ++e) {
      const core::Vec3 a = m.vertices[t[static_cast<std::size_t>(e)]], b = m.vertices[t[static_cast<std::size_t>((e + 1) % 3)]];
      if ((a.z < z) != (b.z < z)) {
        const double s = (z - a.z) / (b.z - a.z);
        hits.push_back({a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)});
      }
    }
    if (hits.size() == 2) out.push_back({hits[0], hits[1]});
  }
  return out;
}

// How far P stands out of the section (negative inside the material), horizontally.
inline double outside_by(P2 p, const std::vector<std::array<P2, 2>>& segs) {
  double d = INFINITY;
  bool in = false;
  for (const auto& [a, b] : segs) {
    d = std::min(d, seg_point(p, a, b));
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in ? -d : d;
}

// A G-code program read as the controller runs it: every G0/G1 block's axis words, the jet's state
// (the process's codes) and the "(layer N region R" block comments.
struct Block {
  machine::MachinePose pose;
  bool jet = false, feed = false;
  int layer = -1, piece = -1;
  std::string phase;  // the last block comment's words after the region: "lead-in", "pass 2", "lead-out", …
};

inline std::vector<Block> read_program(const std::string& text, const std::string& jet_on, const std::string& jet_off) {
  std::vector<Block> out;
  Block cur;
  std::istringstream in(text);
  std::string line;
  const std::regex comment("\\(layer (\\d+) region (\\d+) ?([^)]*)\\)");
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, comment)) cur.layer = std::stoi(m[1]), cur.piece = std::stoi(m[2]), cur.phase = m[3];
    if (line == jet_on) cur.jet = true;
    if (line == jet_off) cur.jet = false;
    if (!(line.starts_with("G0 ") || line.starts_with("G1 "))) continue;
    cur.feed = line.starts_with("G1 ");
    auto word = [&](char c, double& v) {
      const auto at = line.find(std::string(" ") + c);
      if (at != std::string::npos) v = std::stod(line.substr(at + 2));
    };
    word('X', cur.pose.x_mm), word('Y', cur.pose.y_mm), word('Z', cur.pose.z_mm), word('A', cur.pose.a_or_b_deg), word('C', cur.pose.c_deg);
    out.push_back(cur);
  }
  return out;
}

}  // namespace polyaxis::test
