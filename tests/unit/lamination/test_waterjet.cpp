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
#include "support/waterjet_replay.h"
#include "support/repaired.h"

namespace polyaxis::lamination {
namespace {

using test::P2;
using test::Block;
using test::read_program;
using test::ring_distance;
using test::section_segments;
using test::outside_by;
using test::mm;

constexpr double kPi = 3.14159265358979323846;

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
    const auto blocks = read_program(gcode.value(), w.jet_on, w.jet_off);
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
