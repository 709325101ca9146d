// The verifier's shortcut (verify/head_material.h, BelowTheTip): wherever it calls a check clear,
// the full search over the deposit finds nothing, for random deposits, tips, axes, margins and
// turns, on nozzles of several cone angles; and it does call most checks over flat deposit clear.
#include <gtest/gtest.h>

#include <random>

#include "polyaxis/machine/build_model.h"
#include "support/programs.h"
#include "verify/head_material.h"

namespace polyaxis::verify::detail {
namespace {

using core::Vec3;

TEST(BelowTheTip, NeverClearsWhatTheSearchFinds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const std::vector<std::array<float, 3>> axes = {{0, 0, 1}, {0.6f, 0.0f, 0.8f}, {0.0f, -0.28f, 0.96f}};
  std::size_t cleared = 0, checked = 0;
  for (const double cone_deg : {15.0, 30.0, 45.0, 60.0}) {
    machine::MachineConfig m = test::example_machine("ded5_ac");
    m.nozzle.tip_half_angle_deg = cone_deg;
    m.nozzle.cone_height_mm = 8.0 + 12.0 * unit(rng);
    const process::ProcessConfig p = test::default_process();
    const machine::BuildModel model = machine::make_build_model(m, p, -20, -20, 20, 20);
    const double bead = 0.9, radius = std::hypot(0.45, 0.225), ignore = 3.0 * bead;
    // Deposit: layers of beads 0.5 mm apart in z (some tilted), then a few heaps above.
    std::vector<MaterialSample> material;
    for (int k = 0; k < 12; ++k) {
      for (int i = 0; i < 120; ++i) {
        const double x = -15.0 + 0.25 * i, y = 4.0 * std::sin(0.3 * k + 0.05 * i), z = 0.5 * k + 0.1 * u(rng) + (k % 3 == 0 ? 0.05 * x : 0.0);
        material.push_back({{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)}, static_cast<std::uint32_t>(material.size()), k, 0});
      }
    }
    for (int i = 0; i < 300; ++i) {
      const Vec3 c{10.0 * u(rng), 10.0 * u(rng), 6.0 + 8.0 * unit(rng)};
      material.push_back({{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)}, static_cast<std::uint32_t>(material.size()), 99, 1});
    }
    const BelowTheTip below(axes, material, model, radius, ignore);
    const HeadProfile head(model);
    const MaterialIndex index(material);
    for (int q = 0; q < 6000; ++q) {
      const auto& axis = axes[static_cast<std::size_t>(q) % axes.size()];
      const std::array<float, 3> tip{static_cast<float>(16.0 * u(rng)), static_cast<float>(8.0 * u(rng)), static_cast<float>(7.0 + 7.0 * u(rng))};
      const auto before = static_cast<std::uint32_t>(unit(rng) * static_cast<double>(material.size() + 1));
      const double margin = 0.7 * unit(rng), turn = 0.03 * unit(rng);
      ++checked;
      if (!below.clear(tip, axis, before, margin, turn)) continue;
      ++cleared;
      const auto hit = index.deepest(head, {tip[0], tip[1], tip[2]}, {axis[0], axis[1], axis[2]}, before, radius, ignore, margin, turn);
      ASSERT_FALSE(hit.has_value()) << "cone " << cone_deg << " tip (" << tip[0] << ", " << tip[1] << ", " << tip[2] << ") before " << before
                                    << ": the shortcut cleared a check the search finds " << hit->depth_mm << " mm deep";
    }
  }
  // Not vacuous: a good share of the checks above the deposit is cleared.
  EXPECT_GT(cleared, checked / 10);
  EXPECT_LT(cleared, checked);
}

TEST(BelowTheTip, AHeadBoxBelowTheTipTurnsItOff) {
  machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  machine::BuildModel model = machine::make_build_model(m, p, -20, -20, 20, 20);
  const std::vector<MaterialSample> material = {{{0, 0, 0}, 0, 0, 0}};
  EXPECT_TRUE(BelowTheTip({{0, 0, 1}}, material, model, 0.5, 2.7).clear({0, 0, 5}, {0, 0, 1}, 1, 0.1, 0.0));
  model.head_boxes.push_back(machine::HeadBox{{-5, -5, -1}, {5, 5, 3}});
  EXPECT_FALSE(BelowTheTip({{0, 0, 1}}, material, model, 0.5, 2.7).clear({0, 0, 5}, {0, 0, 1}, 1, 0.1, 0.0));
  // Along an axis it keeps no heights for, never.
  EXPECT_FALSE(BelowTheTip({{0, 0, 1}}, material, machine::make_build_model(m, p, -20, -20, 20, 20), 0.5, 2.7)
                   .clear({0, 0, 5}, {1, 0, 0}, 1, 0.1, 0.0));
}

}  // namespace
}  // namespace polyaxis::verify::detail

namespace polyaxis::verify::detail {
namespace {

// The hierarchy finds what a scan of every sample finds: for random clouds (bead-like rows and
// loose heaps, tens of thousands of samples so the parallel build runs), heads with and without
// head boxes, random tips, axes, stamps, margins and turns, the deepest depth is the scan's, and
// with ANY it finds one exactly when the scan does.
TEST(MaterialIndex, FindsWhatAScanOfEverySampleFinds) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  machine::BuildModel model = machine::make_build_model(m, p, -40, -40, 40, 40);
  std::vector<MaterialSample> material;
  for (int k = 0; k < 40; ++k) {
    for (int i = 0; i < 1500; ++i) {
      const double t = 0.3 * i;
      const double x = -30.0 + std::fmod(t, 60.0), y = -30.0 + 1.2 * std::floor(t / 60.0) + 0.3 * u(rng), z = 0.4 * k + 0.05 * u(rng);
      material.push_back({{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)}, static_cast<std::uint32_t>(material.size()), k, 0});
    }
  }
  for (int i = 0; i < 5000; ++i) {
    material.push_back({{static_cast<float>(20.0 * u(rng)), static_cast<float>(20.0 * u(rng)), static_cast<float>(16.0 + 10.0 * unit(rng))},
                        static_cast<std::uint32_t>(material.size()), 50, 1});
  }
  const double radius = std::hypot(0.45, 0.225), ignore = 2.7;
  for (const bool box : {false, true}) {
    if (box) model.head_boxes.push_back(machine::HeadBox{{-6, -3, 4}, {9, 3, 12}});
    const HeadProfile head(model);
    const MaterialIndex index(material);
    std::size_t hits = 0;
    for (int q = 0; q < 400; ++q) {
      const Vec3 tip{30.0 * u(rng), 30.0 * u(rng), 18.0 * unit(rng)};
      const Vec3 axis = core::normalized(Vec3{0.8 * u(rng), 0.8 * u(rng), 1.0});
      const auto before = static_cast<std::uint32_t>(unit(rng) * static_cast<double>(material.size() + 1));
      const double margin = 0.8 * unit(rng), turn = 0.02 * unit(rng);
      std::optional<double> scan;
      for (const MaterialSample& s : material) {
        if (s.stamp >= before) continue;
        const Vec3 pos{s.position[0], s.position[1], s.position[2]};
        const double d = core::norm(pos - tip);
        if (d <= ignore) continue;
        const double sd = head.distance(pos - tip, axis);
        if (sd > radius + margin + turn * d) continue;
        scan = std::max(scan.value_or(-INFINITY), radius - sd);
      }
      const auto found = index.deepest(head, tip, axis, before, radius, ignore, margin, turn);
      ASSERT_EQ(found.has_value(), scan.has_value()) << "query " << q << (box ? " with a head box" : "");
      if (scan) {
        EXPECT_DOUBLE_EQ(found->depth_mm, *scan) << "query " << q;
      }
      EXPECT_EQ(index.deepest(head, tip, axis, before, radius, ignore, margin, turn, true).has_value(), scan.has_value());
      hits += scan ? 1 : 0;
    }
    // Not vacuous: some heads reach the material, some do not.
    EXPECT_GT(hits, 20u);
    EXPECT_LT(hits, 380u);
  }
}

}  // namespace
}  // namespace polyaxis::verify::detail
