// The physical build model (machine/build_model.h): the head's clearance over the plate and the table.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/machine/build_model.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "support/meshes.h"

namespace polyaxis::machine {
namespace {

using process::parse_process;
using process::default_process_json;
using process::ProcessConfig;

constexpr double kPi = 3.14159265358979323846;

struct Fixture {
  MachineConfig m = parse_machine(default_machine_json(), "m").value();
  ProcessConfig p = parse_process(default_process_json(), "p").value();
  BuildModel model = make_build_model(m, p, -20, -30, 20, 30);
};

TEST(BuildModel, ThePlateIsTheFootprintGrownByItsMargin) {
  const Fixture f;
  EXPECT_DOUBLE_EQ(f.model.substrate.x_min_mm, -30.0);
  EXPECT_DOUBLE_EQ(f.model.substrate.x_max_mm, 30.0);
  EXPECT_DOUBLE_EQ(f.model.substrate.y_min_mm, -40.0);
  EXPECT_DOUBLE_EQ(f.model.substrate.y_max_mm, 40.0);
  EXPECT_DOUBLE_EQ(f.model.table_top_z_mm(), -10.0);
  ProcessConfig sized = f.p;
  sized.substrate.size_x_mm = 100, sized.substrate.size_y_mm = 50;
  const BuildModel b = make_build_model(f.m, sized, 0, 0, 20, 20);
  EXPECT_DOUBLE_EQ(b.substrate.x_min_mm, -40.0);
  EXPECT_DOUBLE_EQ(b.substrate.y_max_mm, 35.0);
}

TEST(BuildModel, ClearanceOfTheConeAndCylinderAtEveryTilt) {
  const Fixture f;
  for (double deg = 0.0; deg <= 90.0; deg += 7.5) {
    const double t = deg * kPi / 180.0;
    const Vec3 axis{std::sin(t), 0.0, std::cos(t)};
    // Lowest head point below the tip: the cylinder's bottom rim (r 25 at 20 mm) or its top rim
    // (at 170 mm), or nothing when upright.
    const double rim = std::min({20.0 * std::cos(t) - 25.0 * std::sin(t), 170.0 * std::cos(t) - 25.0 * std::sin(t), 20.0 * std::cos(t)});
    EXPECT_NEAR(head_clearance_mm(f.model, {0, 0, 3}, axis), 3.0 + rim, 1e-9) << deg;
  }
  // Upright, the head is 20 mm above the tip; about 38.7° tilt the rim reaches the tip's height.
  EXPECT_NEAR(head_clearance_mm(f.model, {0, 0, 0}, {0, 0, 1}), 20.0, 1e-9);
  const double t = std::atan(20.0 / 25.0);
  EXPECT_NEAR(head_clearance_mm(f.model, {0, 0, 0}, {std::sin(t), 0, std::cos(t)}), 0.0, 1e-9);
}

TEST(BuildModel, BeyondThePlateTheTableCounts) {
  const Fixture f;
  // Tip 5 mm over the table (z −5), 100 mm out beside the plate, tilted 60° away from it: the rim
  // (r 25) is 21.65 − 10 = 11.65 mm below the tip, over the table (top −10): 6.65 mm into it.
  const double t = 60.0 * kPi / 180.0;
  EXPECT_NEAR(head_clearance_mm(f.model, {100, 0, -5}, {std::sin(t), 0, std::cos(t)}), -5.0 - 11.650635094610966 + 10.0, 1e-9);
  EXPECT_NEAR(tip_clearance_mm(f.model, {100, 0, -5}), 5.0, 1e-12);
  EXPECT_NEAR(tip_clearance_mm(f.model, {0, 0, -0.5}), -0.5, 1e-12);  // under the plate's top
  // Off the table altogether: nothing under the head.
  EXPECT_TRUE(std::isinf(head_clearance_mm(f.model, {1000, 0, -50}, {0, 0, 1})));
}

TEST(BuildModel, HeadBoxesSweptAboutTheAxis) {
  Fixture f;
  // A feeder box 40 mm to the side, from 30 to 60 mm up the nozzle.
  HeadBox box;
  box.min_mm[0] = 30, box.max_mm[0] = 40, box.min_mm[1] = -5, box.max_mm[1] = 5, box.min_mm[2] = 30, box.max_mm[2] = 60;
  f.model.head_boxes.push_back(box);
  const double r = std::hypot(40.0, 5.0);
  const double t = 45.0 * kPi / 180.0;
  const Vec3 axis{std::sin(t), 0, std::cos(t)};
  const double expected = std::min({20.0 * std::cos(t) - 25.0 * std::sin(t), 30.0 * std::cos(t) - r * std::sin(t)});
  EXPECT_NEAR(head_clearance_mm(f.model, {0, 0, 50}, axis), 50.0 + expected, 1e-9);
}

TEST(BuildModel, MachineFileKeys) {
  auto m = parse_machine(R"({"name":"x","kinematics":"xyz","limits":{"x":{"min":0,"max":1},"y":{"min":0,"max":1},"z":{"min":0,"max":1}},
    "feed":{"linear_max_mm_min":100},"table":{"radius_mm":120},"head_boxes":[{"min_mm":[0,0,30],"max_mm":[10,10,40]}]})",
                         "m");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_DOUBLE_EQ(m.value().table.radius_mm, 120.0);
  ASSERT_EQ(m.value().head_boxes.size(), 1u);
  EXPECT_DOUBLE_EQ(m.value().head_boxes[0].max_mm[2], 40.0);
  auto bad = parse_machine(R"({"name":"x","kinematics":"xyz","limits":{"x":{"min":0,"max":1},"y":{"min":0,"max":1},"z":{"min":0,"max":1}},
    "feed":{"linear_max_mm_min":100},"head_boxes":[{"min_mm":[0,0,50],"max_mm":[10,10,40]}]})",
                           "m");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("head_boxes[0]"), std::string::npos) << bad.error().message;
  auto p = parse_process(R"({"name":"p","bead_width_mm":1,"layer_mm":0.5,"deposit_feed_mm_s":5,"travel_feed_mm_s":50,
    "process_on":"M64 P0","process_off":"M65 P0","max_step_bead_share":1.5})",
                         "p");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().message.find("max_step_bead_share"), std::string::npos);
}

// Every point of a surface is within spacing / √3 of a sample, each sample lies on the surface with
// its face's outward normal, and slivers, huge triangles and bad input neither hang nor flood.
TEST(PrebuiltBody, SamplesCoverTheSurfaceAtTheSpacing) {
  struct Case {
    std::vector<Vec3> v;
    std::vector<std::array<std::uint32_t, 3>> t;
  };
  auto raw = [](const io::RawMesh& m) { return Case{m.points, m.triangles}; };
  const std::vector<Case> cases = {
      raw(test::box({0, 0, 0}, {7, 3, 11})),
      raw(test::spherical_cap(20, 8, 30, 6)),
      {{{0, 0, 0}, {40, 0, 0}, {40, 0.01, 0}}, {{0, 1, 2}}},  // a sliver
  };
  for (const double spacing : {0.3, 1.0}) {
    for (const Case& c : cases) {
      PrebuiltBody body;
      ASSERT_TRUE(add_prebuilt(body, c.v, c.t, spacing));
      ASSERT_EQ(body.surface_mm.size(), body.normals.size());
      // Linear in the area / spacing² and the edges' length / spacing.
      double area = 0.0, edges = 0.0;
      for (const auto& tri : c.t) {
        area += 0.5 * core::norm(core::cross(c.v[tri[1]] - c.v[tri[0]], c.v[tri[2]] - c.v[tri[0]]));
        for (int k = 0; k < 3; ++k) edges += core::norm(c.v[tri[(k + 1) % 3]] - c.v[tri[k]]);
      }
      EXPECT_LT(static_cast<double>(body.surface_mm.size()), 8.0 * area / (spacing * spacing) + 20.0 * edges / spacing + 3.0 * static_cast<double>(c.t.size()));
      std::uint32_t seed = 7;
      auto rnd = [&] { return (seed = seed * 1664525u + 1013904223u) / 4294967296.0; };
      for (const auto& tri : c.t) {
        const Vec3 a = c.v[tri[0]], b = c.v[tri[1]], d = c.v[tri[2]];
        const Vec3 n = core::normalized(core::cross(b - a, d - a));
        for (int k = 0; k < 20; ++k) {
          double u = rnd(), w = rnd();
          if (u + w > 1.0) u = 1.0 - u, w = 1.0 - w;
          const Vec3 p = a + (b - a) * u + (d - a) * w;
          double nearest = INFINITY;
          for (const Vec3& q : body.surface_mm) nearest = std::min(nearest, core::norm(q - p));
          EXPECT_LE(nearest, spacing / std::sqrt(3.0) + 1e-9);
        }
        for (std::size_t i = 0; i < body.surface_mm.size(); ++i) {
          if (core::dot(body.normals[i], n) < 1.0 - 1e-9) continue;  // another face's sample
          EXPECT_NEAR(core::dot(body.surface_mm[i] - a, n), 0.0, 1e-9);
        }
      }
    }
  }
  PrebuiltBody none;
  EXPECT_TRUE(add_prebuilt(none, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, 0.0));
  EXPECT_TRUE(add_prebuilt(none, {{0, 0, 0}, {INFINITY, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, 0.5));
  EXPECT_TRUE(add_prebuilt(none, {{0, 0, 0}, {NAN, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, 0.5));
  EXPECT_TRUE(none.empty());
}

// A surface too large for the spacing is refused, the body left as it was, before the samples
// take the memory: a fuzzed plan.json with a prebuilt region stretched 9 m (a vertex at Y 9190)
// took 27 s and 2.4 GB to read (tests/fuzz/corpus/plan_json/prebuilt_9m.json).
TEST(BuildModel, APrebuiltSurfaceTooLargeForTheSpacingIsRefused) {
  PrebuiltBody body;
  ASSERT_TRUE(add_prebuilt(body, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, 0.36));
  const std::size_t before = body.surface_mm.size();
  const std::vector<Vec3> v{{-15, -10, 40}, {-15, 9190, 40}, {-15, 10, 60}};  // 9200 mm by 20 mm
  EXPECT_FALSE(add_prebuilt(body, v, {{0, 1, 2}}, 0.36, 100'000));
  EXPECT_EQ(body.surface_mm.size(), before);
  EXPECT_EQ(body.normals.size(), before);
  // The same face at a spacing it fits in is sampled.
  EXPECT_TRUE(add_prebuilt(body, v, {{0, 1, 2}}, 10.0, 100'000));
  EXPECT_GT(body.surface_mm.size(), before);
}

}  // namespace
}  // namespace polyaxis::machine
