// Nesting (exact distance checks written here) and the waterjet programs read back through the
// machine's forward kinematics: every jet-on pose lies on the planned path, and the jet's line never
// enters the part (half a kerf of clearance) anywhere in its sheet.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <sstream>

#include "polyaxis/lamination/lamination.h"
#include "polyaxis/lamination/nest.h"
#include "polyaxis/lamination/waterjet.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/post/gcode.h"
#include "support/meshes.h"
#include "support/repaired.h"

namespace polyaxis::lamination {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct P2 {
  double x, y;
};

double seg_point(P2 p, P2 a, P2 b) {
  const double ex = b.x - a.x, ey = b.y - a.y, l2 = ex * ex + ey * ey;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - a.x - t * ex, p.y - a.y - t * ey);
}

bool cross(P2 a, P2 b, P2 c, P2 d) {
  auto o = [](P2 p, P2 q, P2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
  return o(a, b, c) * o(a, b, d) < 0 && o(c, d, a) * o(c, d, b) < 0;
}

std::vector<P2> mm(const geom2d::Ring& r) {
  std::vector<P2> out;
  for (const auto& p : r) out.push_back({geom2d::to_mm(p.x), geom2d::to_mm(p.y)});
  return out;
}

bool inside(P2 p, const std::vector<P2>& ring) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    if ((ring[i].y > p.y) != (ring[j].y > p.y) && p.x < (ring[j].x - ring[i].x) * (p.y - ring[i].y) / (ring[j].y - ring[i].y) + ring[i].x) in = !in;
  }
  return in;
}

// The least distance between two rings that do not cross, or 0 when they cross or nest.
double ring_distance(const std::vector<P2>& a, const std::vector<P2>& b) {
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
std::vector<std::array<P2, 2>> section_segments(const mesh::Mesh& m, double z) {
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
double outside_by(P2 p, const std::vector<std::array<P2, 2>>& segs) {
  double d = INFINITY;
  bool in = false;
  for (const auto& [a, b] : segs) {
    d = std::min(d, seg_point(p, a, b));
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in ? -d : d;
}

geom2d::Ring circle(double r, int n, double cx = 0, double cy = 0) {
  geom2d::Ring ring;
  for (int i = 0; i < n; ++i) ring.push_back({geom2d::to_units(cx + r * std::cos(2 * kPi * i / n)), geom2d::to_units(cy + r * std::sin(2 * kPi * i / n))});
  return ring;
}

geom2d::Ring polygon(std::initializer_list<P2> pts) {
  geom2d::Ring ring;
  for (const auto& p : pts) ring.push_back({geom2d::to_units(p.x), geom2d::to_units(p.y)});
  return ring;
}

TEST(Nest, PiecesKeepTheSpacingFromEachOtherAndTheSheetEdge) {
  std::vector<geom2d::Ring> outlines;
  for (int i = 0; i < 7; ++i) outlines.push_back(circle(10.0 + 4.0 * i, 24 + 8 * i, 100.0 * i, -50.0));
  for (int i = 0; i < 5; ++i) outlines.push_back(polygon({{0, 0}, {60, 0}, {60, 15}, {15, 15}, {15, 40}, {0, 40}}));  // L, not convex
  outlines.push_back(polygon({{0, 0}, {120, 0}, {120, 8}, {0, 8}}));
  const NestOptions o{200.0, 150.0, 4.0};
  auto r = nest(outlines, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto& pl = r.value();
  std::uint32_t sheets = 0;
  std::vector<std::vector<P2>> placed;
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    placed.push_back(mm(place(pl[i], outlines[i])));
    sheets = std::max(sheets, pl[i].sheet + 1);
    EXPECT_EQ(std::fmod(pl[i].rotation_deg, 90.0), 0.0);
    for (const auto& p : placed.back()) {  // the least distance to a straight edge is at a vertex
      EXPECT_GE(std::min({p.x, p.y, o.sheet_w_mm - p.x, o.sheet_h_mm - p.y}), o.spacing_mm - 1e-6) << i;
    }
  }
  for (std::size_t i = 0; i < placed.size(); ++i) {
    for (std::size_t j = i + 1; j < placed.size(); ++j) {
      if (pl[i].sheet == pl[j].sheet) {
        EXPECT_GE(ring_distance(placed[i], placed[j]), o.spacing_mm - 1e-6) << i << " " << j;
      }
    }
  }
  EXPECT_LE(sheets, 4u);
}

TEST(Nest, APieceNoSheetHoldsIsInfeasible) {
  auto r = nest({circle(80.0, 64)}, NestOptions{150.0, 150.0, 3.0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::kInfeasible);
  EXPECT_EQ(nest({circle(5.0, 16)}, NestOptions{100.0, 0.0, 3.0}).error().code, core::ErrorCode::kUsage);
}

WaterjetProcess default_process() { return parse_waterjet_process(default_waterjet_process_json(), "default").value(); }
machine::MachineConfig default_machine() { return machine::parse_machine(default_waterjet_machine_json(), "default").value(); }

TEST(Waterjet, FeedFollowsEquation3) {
  const WaterjetProcess p = default_process();
  // 6 mm of mild steel at μ = 130 GJ/m³, d0 0.33 mm, di 1.02 mm, R 0.2, 380 MPa: by hand from Eq. 3,
  // 1.18792e-8 m² · 7.40757e12 Pa^1.5 · 0.0447214 / (1.3e11 · 1.02e-3 · 6e-3) = 4.946 mm/s (297 mm/min).
  EXPECT_NEAR(waterjet_feed_mm_s(p, 6.0, 0.0), 4.946, 0.001);
  EXPECT_NEAR(waterjet_feed_mm_s(p, 3.0, 0.0), 2.0 * waterjet_feed_mm_s(p, 6.0, 0.0), 1e-9);  // ∝ 1/h
  EXPECT_NEAR(waterjet_feed_mm_s(p, 6.0, kPi / 3), 0.5 * waterjet_feed_mm_s(p, 6.0, 0.0), 1e-9);  // h = t / cos 60°
  EXPECT_EQ(waterjet_feed_mm_s(p, 0.01, 0.0), p.max_feed_mm_s);
}

TEST(Waterjet, ProcessFileIsCheckedKeyByKey) {
  const WaterjetProcess p = default_process();
  EXPECT_EQ(p.kerf_mm, 0.8);
  std::string text(default_waterjet_process_json());
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return parse_waterjet_process(t, "w.json");
  };
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{"\"kerf_mm\": 0.8", "\"kerf_mm\": -1"},
                                                                                 {"\"jet_on\": \"M64 P0\"", "\"jet_on\": \"G0 X10\""},
                                                                                 {"\"jet_off\": \"M65 P0\"", "\"jet_off\": \"M2\""},
                                                                                 {"\"lead_in_mm\": 2", "\"lead_in_mm\": 4"},
                                                                                 {"\"pierce_s\": 1.5", "\"pierce_s\": 1.5, \"speed\": 3"},
                                                                                 {"\"max_feed_mm_s\": 60", "\"max_feed_mm_s\": 0.1"}}) {
    auto r = with(from, to);
    ASSERT_FALSE(r.ok()) << to;
    EXPECT_EQ(r.error().code, core::ErrorCode::kUsage) << to;
    EXPECT_NE(r.error().message.find("w.json"), std::string::npos);
  }
}

// A G-code program read as the controller runs it: every G0/G1 block's axis words, the jet's state
// (the process's codes) and the "(layer N region R" block comments.
struct Block {
  machine::MachinePose pose;
  bool jet = false, feed = false;
  int layer = -1, piece = -1;
};

std::vector<Block> read_program(const std::string& text, const WaterjetProcess& w) {
  std::vector<Block> out;
  Block cur;
  std::istringstream in(text);
  std::string line;
  const std::regex comment("\\(layer (\\d+) region (\\d+)");
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, comment)) cur.layer = std::stoi(m[1]), cur.piece = std::stoi(m[2]);
    if (line == w.jet_on) cur.jet = true;
    if (line == w.jet_off) cur.jet = false;
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

// Laminates M, writes every sheet's program and reads it back: jet-on poses on the plan's path,
// the jet's line outside the part by half a kerf (less TOL_MM) within the sheet.
void replay(const mesh::Mesh& m, const LaminateOptions& o, const char* name) {
  const WaterjetProcess w = default_process();
  const machine::MachineConfig machine = default_machine();
  auto lam = laminate(m, o);
  ASSERT_TRUE(lam.ok()) << lam.error().message;
  auto sheets = nest_sheets(lam.value(), w, 300.0, 300.0, machine);
  ASSERT_TRUE(sheets.ok()) << sheets.error().message;
  std::map<double, std::vector<std::array<P2, 2>>> sections;  // by height, cut on first use
  double worst_gouge = -INFINITY, worst_off_path = 0.0;
  std::size_t jet_samples = 0;
  for (const auto& sheet : sheets.value()) {
    auto points = sheet_program(lam.value(), sheet, w, machine);
    ASSERT_TRUE(points.ok());
    auto gcode = sheet_gcode(lam.value(), sheet, w, machine);
    ASSERT_TRUE(gcode.ok()) << gcode.error().message;
    std::vector<core::Vec3> path;  // planned jet-on tips, in order
    for (const auto& p : points.value()) path.push_back(p.tip_part_mm);
    std::map<std::pair<int, int>, Placement> placement;
    for (const auto& sp : sheet.pieces) placement[{static_cast<int>(sp.layer), static_cast<int>(sp.piece)}] = sp.placement;
    const auto blocks = read_program(gcode.value(), w);
    for (std::size_t b = 1; b < blocks.size(); ++b) {
      if (!blocks[b].jet || !blocks[b].feed) continue;
      const Layer& layer = lam.value().layers.at(static_cast<std::size_t>(blocks[b].layer));
      const Placement& pl = placement.at({blocks[b].layer, blocks[b].piece});
      for (int k = 1; k <= 4; ++k) {  // joint-linear between block ends, as the controller moves
        const double s = k / 4.0;
        machine::MachinePose q;
        const auto& a = blocks[b - 1].pose;
        const auto& e = blocks[b].pose;
        q.x_mm = a.x_mm + s * (e.x_mm - a.x_mm), q.y_mm = a.y_mm + s * (e.y_mm - a.y_mm), q.z_mm = a.z_mm + s * (e.z_mm - a.z_mm);
        q.a_or_b_deg = a.a_or_b_deg + s * (e.a_or_b_deg - a.a_or_b_deg), q.c_deg = a.c_deg + s * (e.c_deg - a.c_deg);
        const auto tool = machine::forward(machine, q);
        if (k == 4) {  // the block's end is on the plan's path
          double off = INFINITY;
          for (std::size_t i = 1; i < path.size(); ++i) {
            const core::Vec3 u = path[i] - path[i - 1];
            const double l2 = core::dot(u, u);
            const double t = l2 > 0 ? std::clamp(core::dot(tool.tip_part_mm - path[i - 1], u) / l2, 0.0, 1.0) : 0.0;
            off = std::min(off, core::norm(tool.tip_part_mm - path[i - 1] - u * t));
          }
          worst_off_path = std::max(worst_off_path, off);
        }
        EXPECT_NEAR(tool.tip_part_mm.z, layer.thickness_mm, 0.011);  // the post's chordal tolerance
        // Down the jet through the sheet, back into the part's frame; its centre must stand half a
        // kerf out of the part's section at every height of the sheet (just inside its faces).
        for (int j = 0; j <= 8; ++j) {
          const double depth = std::clamp(layer.thickness_mm * j / 8.0, 1e-3, layer.thickness_mm - 1e-3);
          const core::Vec3 on = tool.tip_part_mm - tool.tool_axis_part * (depth / tool.tool_axis_part.z);
          const double sx = on.x - sheet.origin_mm[0] - pl.dx_mm, sy = on.y - sheet.origin_mm[1] - pl.dy_mm;
          const double c = std::cos(pl.rotation_deg * kPi / 180.0), sn = std::sin(pl.rotation_deg * kPi / 180.0);
          const core::Vec3 part{c * sx + sn * sy, -sn * sx + c * sy, layer.z_bottom_mm + on.z};
          auto& segs = sections[part.z];
          if (segs.empty()) segs = section_segments(m, part.z);
          const double g = 0.5 * w.kerf_mm - outside_by({part.x, part.y}, segs);
          worst_gouge = std::max(worst_gouge, g);
          ++jet_samples;
        }
      }
    }
  }
  std::printf("%s: %zu sheets, %zu jet samples; worst gouge %.4f mm, farthest from the path %.4f mm\n", name, sheets.value().size(), jet_samples,
              worst_gouge, worst_off_path);
  EXPECT_GT(jet_samples, 0u);
  EXPECT_LE(worst_gouge, 0.02) << name << ": the jet enters the part";
  EXPECT_LE(worst_off_path, 0.011) << name;  // the post's chordal tolerance and 4-decimal words
}

TEST(Waterjet, ProgramsReplayOntoThePlannedEdgesWithoutGouging) {
  LaminateOptions o;
  o.sheets_mm = {2, 6};
  o.area_deviation = 0.3;
  o.max_jet_angle_deg = 60.0;
  std::vector<std::array<double, 2>> neck;
  for (int k = 0; k <= 24; ++k) {
    const double z = 24.0 * k / 24.0, s = (z - 12.0) / 12.0;
    neck.push_back({8.0 + 12.0 * s * s, z});
  }
  replay(test::repaired(test::revolve(neck, 64, 4.0)).mesh, o, "spool with bore");
  std::vector<std::array<double, 2>> ball;
  for (int k = 0; k <= 24; ++k) {
    const double a = -kPi / 2 + kPi * k / 24.0;
    ball.push_back({std::max(15.0 * std::cos(a), 1.0), 15.0 + 15.0 * std::sin(a)});
  }
  replay(test::repaired(test::revolve(ball, 64)).mesh, o, "ball");
}

}  // namespace
}  // namespace polyaxis::lamination
