// The physical build model (machine/build_model.h): the head's clearance over the plate and the table.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

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
  BuildModel wide = make_build_model(m, p, -200, -200, 200, 200);  // a plate under every head below
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
    // Lowest head point below the tip: the cone's end 1 mm up (r tan 30°: the millimetre below is
    // the tip's own), the cylinder's bottom rim (r 25 at 20 mm) or its top rim (at 170 mm).
    const double cone = std::cos(t) - std::tan(kPi / 6.0) * std::sin(t);
    const double rim = std::min({20.0 * std::cos(t) - 25.0 * std::sin(t), 170.0 * std::cos(t) - 25.0 * std::sin(t), cone});
    EXPECT_NEAR(head_clearance_mm(f.wide, {0, 0, 3}, axis), 3.0 + rim, 1e-9) << deg;
  }
  // Upright, the cone 1 mm up is the lowest; about 38.7° tilt the rim reaches the tip's height.
  EXPECT_NEAR(head_clearance_mm(f.wide, {0, 0, 0}, {0, 0, 1}), 1.0, 1e-9);
  const double t = std::atan(20.0 / 25.0);
  EXPECT_NEAR(head_clearance_mm(f.wide, {0, 0, 0}, {std::sin(t), 0, std::cos(t)}), 0.0, 1e-9);
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

// The lowest point of the head's solids over the plate's rectangle grown by GROW_MM, from points
// filling them (every point sampled is a point of the head); SPACING: a bound on the distance from
// any head point to the nearest sample.
double sampled_over_plate(const BuildModel& m, Vec3 tip, Vec3 axis, double grow_mm, double* spacing) {
  const Vec3 a = core::normalized(axis);
  const Vec3 u = core::normalized(core::cross(a, std::abs(a.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0})), v = core::cross(a, u);
  const SubstratePlate& p = m.substrate;
  const double tan30 = std::tan(kPi / 6.0);
  struct Solid {
    double s0, r0, s1, r1;
  };
  double low = INFINITY;
  *spacing = 0.0;
  for (const Solid& s : {Solid{1.0, tan30, 20.0, 20.0 * tan30}, Solid{20.0, 25.0, 170.0, 25.0}}) {
    const int nl = 80, nr = 16, nphi = 240;
    *spacing = std::max({*spacing, (s.s1 - s.s0) / nl, s.r1 / nr, 2.0 * kPi * s.r1 / nphi});
    for (int i = 0; i <= nl; ++i) {
      const double l = static_cast<double>(i) / nl, r = s.r0 + (s.r1 - s.r0) * l;
      const Vec3 c = tip + a * (s.s0 + (s.s1 - s.s0) * l);
      for (int j = 0; j <= nr; ++j) {
        for (int k = 0; k < (j == 0 ? 1 : nphi); ++k) {
          const double phi = 2.0 * kPi * k / nphi, rho = r * j / nr;
          const Vec3 q = c + u * (rho * std::cos(phi)) + v * (rho * std::sin(phi));
          if (q.x >= p.x_min_mm - grow_mm && q.x <= p.x_max_mm + grow_mm && q.y >= p.y_min_mm - grow_mm && q.y <= p.y_max_mm + grow_mm) {
            low = std::min(low, q.z);
          }
        }
      }
    }
  }
  return low - p.top_z_mm;
}

TEST(BuildModel, OverThePlatesEdgeOnlyTheHeadsPartOverThePlateCounts) {
  // The plate's rectangle [-30, 30] × [-40, 40], no table under the head: the clearance is the
  // lowest point of the head's part over the plate, exactly. Against points filling the head, at
  // tips and axes all about the plate's edges and corners: no head point over the plate is lower
  // than the clearance, and some point within the spacing of the plate is within it of the clearance.
  Fixture f;
  f.model.table_centre_mm = {1e9, 0, 0};
  std::uint64_t seed = 12345;
  auto uniform = [&](double lo, double hi) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(seed >> 11) / 9007199254740992.0;
  };
  int straddling = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 tip{uniform(-60, 60), uniform(-70, 70), uniform(-5, 30)};
    const double tilt = uniform(0, 100) * kPi / 180.0, azimuth = uniform(0, 2 * kPi);
    const Vec3 axis{std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt)};
    double spacing = 0.0;
    const double sampled = sampled_over_plate(f.model, tip, axis, 0.0, &spacing);
    const double near = sampled_over_plate(f.model, tip, axis, spacing, &spacing);
    const double exact = head_clearance_mm(f.model, tip, axis);
    EXPECT_LE(exact, sampled + 1e-9) << trial << " tip " << tip.x << " " << tip.y << " " << tip.z;
    if (std::isinf(exact)) {
      EXPECT_TRUE(std::isinf(sampled)) << trial;
      continue;
    }
    EXPECT_GE(exact, near - spacing) << trial << " tip " << tip.x << " " << tip.y << " " << tip.z;
    straddling += std::abs(tip.x) > 5 || std::abs(tip.y) > 15;
  }
  EXPECT_GT(straddling, 30);
  // A head tilted away over the plate's edge: its rim dips 9.6 mm below the tip beyond the edge,
  // over the table, while its part over the plate stays above the tip's height less the cone's.
  Fixture g;
  const double t = 60.0 * kPi / 180.0;
  const double over_table = head_clearance_mm(g.model, {29, 0, 2}, {std::sin(t), 0, std::cos(t)});
  EXPECT_NEAR(over_table, 2.0 + 20.0 * std::cos(t) - 25.0 * std::sin(t) + 10.0, 1e-9);  // the table's top is −10
}

TEST(BuildModel, HeadBoxesSweptAboutTheAxis) {
  Fixture f;
  // A feeder box 40 mm to the side, from 30 to 60 mm up the nozzle.
  HeadBox box;
  box.min_mm[0] = 30, box.max_mm[0] = 40, box.min_mm[1] = -5, box.max_mm[1] = 5, box.min_mm[2] = 30, box.max_mm[2] = 60;
  f.wide.head_boxes.push_back(box);
  const double r = std::hypot(40.0, 5.0);
  const double t = 45.0 * kPi / 180.0;
  const Vec3 axis{std::sin(t), 0, std::cos(t)};
  const double expected = std::min({20.0 * std::cos(t) - 25.0 * std::sin(t), 30.0 * std::cos(t) - r * std::sin(t)});
  EXPECT_NEAR(head_clearance_mm(f.wide, {0, 0, 50}, axis), 50.0 + expected, 1e-9);
}

TEST(BuildModel, AClearanceAskedForBelowAThresholdIsExactBelowItAndAtLeastItAbove) {
  // head_clearance_mm(…, T): the exact clearance where that is below T, else a value of at least T
  // (the bound callers compare with T get). Random tips and axes (some pointing down, a head box
  // reaching below the tip) about a plate, with thresholds on both sides of the exact value.
  Fixture f;
  HeadBox box;
  box.min_mm[0] = 10, box.max_mm[0] = 35, box.min_mm[1] = -8, box.max_mm[1] = 8, box.min_mm[2] = -2, box.max_mm[2] = 45;
  f.model.head_boxes.push_back(box);
  std::uint64_t seed = 777;
  auto uniform = [&](double lo, double hi) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(seed >> 11) / 9007199254740992.0;
  };
  int bounded = 0, exact_asked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 tip{uniform(-60, 60), uniform(-70, 70), uniform(-5, 80)};
    const double tilt = uniform(0, 120) * kPi / 180.0, azimuth = uniform(0, 2 * kPi);
    const Vec3 axis{std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt)};
    const double exact = head_clearance_mm(f.model, tip, axis);
    const double threshold = uniform(-5, 40);
    const double asked = head_clearance_mm(f.model, tip, axis, threshold);
    if (exact < threshold) {
      EXPECT_DOUBLE_EQ(asked, exact) << trial;
      ++exact_asked;
    } else {
      EXPECT_GE(asked, threshold) << trial;
      EXPECT_LE(asked, exact + 1e-9) << trial;
      bounded += asked < exact - 1e-9;
    }
  }
  EXPECT_GT(exact_asked, 200);
  EXPECT_GT(bounded, 200);  // the bound answered
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
