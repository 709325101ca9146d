// Which build directions a machine can take (planner/reach.h): a table-table machine turns any
// direction within its tilt reach up; a head-head machine leaves the part fixed, so a region may
// lean only as far off vertical as the process deposits (off_vertical_max_deg), and a region
// beyond is refused naming that key rather than the tilt axis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "planner/reach.h"
#include "polyaxis/post/gcode.h"
#include "support/programs.h"

namespace polyaxis::planner::detail {
namespace {

constexpr double kDeg = M_PI / 180.0;

PlanRegion leaning(std::uint32_t id, double deg) {
  PlanRegion r;
  r.id = id;
  r.direction = {std::sin(deg * kDeg), 0.0, std::cos(deg * kDeg)};
  return r;
}

TEST(Reach, AHeadHeadMachineTakesTheProcessesAngleOffVertical) {
  machine::MachineConfig table = test::example_machine("ded5_ac");
  machine::MachineConfig head = test::example_machine("ded5_head_bc");
  process::ProcessConfig p = test::default_process();
  EXPECT_NEAR(direction_reach_rad(table, p), 120.0 * kDeg, 1e-12);  // the part turns: A's reach
  EXPECT_NEAR(reach_rad(head), 110.0 * kDeg, 1e-12);               // the torch tilts as far as B goes
  EXPECT_EQ(direction_reach_rad(head, p), 0.0);                    // but gravity stays: straight up
  p.off_vertical_max_deg = 35.0;
  EXPECT_NEAR(direction_reach_rad(head, p), 35.0 * kDeg, 1e-12);
  p.off_vertical_max_deg = 89.0;
  head.tilt_deg = {-60.0, 60.0};
  EXPECT_NEAR(direction_reach_rad(head, p), 60.0 * kDeg, 1e-12);  // and never beyond the head's tilt
}

TEST(Reach, ARegionLeaningFurtherThanTheProcessDepositsIsRefusedNamingTheKey) {
  const machine::MachineConfig head = test::example_machine("ded5_head_bc");
  process::ProcessConfig p = test::default_process();
  p.off_vertical_max_deg = 30.0;
  EXPECT_TRUE(check_region_reach({leaning(0, 0.0), leaning(1, 29.0)}, head, p).ok());
  const auto refused = check_region_reach({leaning(0, 0.0), leaning(1, 29.0), leaning(2, 45.0)}, head, p);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, core::ErrorCode::kMachineLimit);
  for (const char* word : {"region 2", "45.0 deg from vertical", "off_vertical_max_deg", "ded5_head_bc"}) {
    EXPECT_NE(refused.error().message.find(word), std::string::npos) << word << ": " << refused.error().message;
  }
  // On a table-table machine the same lean is a tilt the table makes.
  EXPECT_TRUE(check_region_reach({leaning(0, 0.0), leaning(2, 45.0)}, test::example_machine("ded5_ac"), p).ok());
  const auto beyond = check_region_reach({leaning(3, 130.0)}, test::example_machine("ded5_ac"), p);
  ASSERT_FALSE(beyond.ok());
  EXPECT_NE(beyond.error().message.find("limits.a"), std::string::npos) << beyond.error().message;
}

TEST(Reach, AMoveWhoseEndsClearThePlateCanStillCrossItsEdge) {
  // The robot cell's slim torch (a cone of 15° half-angle, 40 mm long, under a 12 mm cylinder) level
  // 8.5 mm over the plate, 28 mm in from two of its edges by a corner. Pointing out over one edge,
  // the cone there is 28·tan 15° = 7.5 mm wide, 1 mm above the plate, and the rest hangs over the
  // table 10 mm lower: clear. Turned about the tip to the other edge, the same. Half way it points
  // at the corner, 39.6 mm away, where the cone is 10.6 mm wide: 2.1 mm into the plate. The move
  // between two clear poses is not clear.
  machine::BuildModel model;
  model.nozzle = test::example_machine("robot_abb_positioner").nozzle;
  model.substrate = {-50.0, -50.0, 50.0, 50.0, 0.0, 10.0};
  const Vec3 tip{-22.0, -22.0, 8.5};
  const Vec3 out_y{0.0, -1.0, 0.0}, out_x{-1.0, 0.0, 0.0}, corner = core::normalized(Vec3{-1.0, -1.0, 0.0});
  EXPECT_NEAR(machine::head_clearance_mm(model, tip, out_y), 8.5 - 28.0 * std::tan(15.0 * kDeg), 1e-6);
  EXPECT_NEAR(machine::head_clearance_mm(model, tip, out_x), 8.5 - 28.0 * std::tan(15.0 * kDeg), 1e-6);
  EXPECT_NEAR(machine::head_clearance_mm(model, tip, corner), 8.5 - 28.0 * std::sqrt(2.0) * std::tan(15.0 * kDeg), 1e-6);
  EXPECT_FALSE(move_clear(model, 0.0, tip, out_y, tip, out_x));
  EXPECT_TRUE(move_clear(model, 0.0, tip, out_y, tip, out_y));
  // Moving up while it turns, the head stays clear.
  EXPECT_TRUE(move_clear(model, 0.0, tip, out_y, tip + Vec3{0.0, 0.0, 40.0}, out_x));
}

Vec3 axis_at(double tilt_deg, double azimuth_deg) {
  return {std::sin(tilt_deg * kDeg) * std::cos(azimuth_deg * kDeg), std::sin(tilt_deg * kDeg) * std::sin(azimuth_deg * kDeg),
          std::cos(tilt_deg * kDeg)};
}

// The great circle between two axes below the horizon at distant azimuths dips towards −Z: between
// 105° at azimuths 0° and 110° it reaches 115°, and at 0° and 140°, 128.08°. The largest tilt along
// an arc is checked against dense sampling, at many ends.
TEST(Reach, TheLargestTiltAlongAnArcIsWhereItDips) {
  EXPECT_NEAR(max_tilt_on_arc_rad(axis_at(105, 0), axis_at(105, 0)), 105.0 * kDeg, 1e-9);
  EXPECT_NEAR(max_tilt_on_arc_rad(axis_at(30, 0), axis_at(60, 90)), 60.0 * kDeg, 1e-9);  // above the horizon: an end
  for (int k = 0; k < 400; ++k) {
    const Vec3 a = axis_at(10.0 + (k * 37) % 160, (k * 53) % 360), b = axis_at(10.0 + (k * 71) % 160, (k * 29) % 360);
    if (std::acos(std::clamp(core::dot(a, b), -1.0, 1.0)) > 175.0 * kDeg) continue;
    double sampled = 0.0;
    const double w = std::acos(std::clamp(core::dot(a, b), -1.0, 1.0));
    for (int s = 0; s <= 2000; ++s) {
      const double u = s / 2000.0;
      const Vec3 p = w < 1e-12 ? a : core::normalized(a * (std::sin((1 - u) * w) / std::sin(w)) + b * (std::sin(u * w) / std::sin(w)));
      sampled = std::max(sampled, std::acos(std::clamp(p.z, -1.0, 1.0)));
    }
    EXPECT_NEAR(max_tilt_on_arc_rad(a, b), sampled, 1e-5) << k;
  }
  EXPECT_NEAR(max_tilt_on_arc_rad(axis_at(105, 0), axis_at(105, 110)), 115.0 * kDeg, 0.1 * kDeg);
  EXPECT_NEAR(max_tilt_on_arc_rad(axis_at(105, 0), axis_at(105, 140)), 128.08 * kDeg, 0.01 * kDeg);
}

// Turned within the reach instead: every step's great circle keeps within 120°, the steps are
// short, and they run from one end to the other. None is needed where the great circle keeps within.
TEST(Reach, AxesBelowTheHorizonTurnRoundWithinTheReach) {
  const double reach = 120.0 * kDeg;
  EXPECT_TRUE(axes_within_reach(axis_at(105, 0), axis_at(105, 20), reach).empty());
  EXPECT_TRUE(axes_within_reach(axis_at(40, 0), axis_at(60, 170), reach).empty());
  for (const auto& [a, b] : {std::pair{axis_at(105, 0), axis_at(105, 140)}, std::pair{axis_at(120, -30), axis_at(118, 150)},
                             std::pair{axis_at(110, 150), axis_at(119.99, -150)}}) {
    ASSERT_GT(max_tilt_on_arc_rad(a, b), reach);
    const std::vector<Vec3> via = axes_within_reach(a, b, reach);
    ASSERT_FALSE(via.empty());
    std::vector<Vec3> all{a};
    all.insert(all.end(), via.begin(), via.end());
    all.push_back(b);
    for (std::size_t i = 1; i < all.size(); ++i) {
      EXPECT_LE(max_tilt_on_arc_rad(all[i - 1], all[i]), reach + 1e-9) << i;
      EXPECT_LE(std::acos(std::clamp(core::dot(all[i - 1], all[i]), -1.0, 1.0)), 1.5 * kDeg) << i;
      EXPECT_NEAR(core::norm(all[i]), 1.0, 1e-12);
    }
  }
}

// The height over the plate at which the head can lay a region built at a tilt: nothing while the
// torch can stand upright enough (up to the layer normal's 60° plus what keeps the default head's
// cylinder, r 25 mm from 20 mm up, off the plate), then growing with the tilt; at that height the
// head itself keeps the clearance asked for, and 1 mm lower it does not.
TEST(Reach, TheHeadLaysARegionBuiltFarOverOnlyHighEnoughAboveThePlate) {
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  const double clearance = 0.5;
  EXPECT_EQ(least_layable_height_mm(m, p, 0.0, clearance), 0.0);
  EXPECT_EQ(least_layable_height_mm(m, p, 90.0 * kDeg, clearance), 0.0);  // the axis 30° over: its cylinder's rim 4.8 mm up
  double before = 0.0;
  for (double deg = 100.0; deg <= 150.0; deg += 10.0) {
    SCOPED_TRACE(deg);
    const double need = least_layable_height_mm(m, p, deg * kDeg, clearance);
    EXPECT_GT(need, before);
    before = need;
    const double t = (deg - 60.0) * kDeg;
    // The cylinder's lowest rim point sets it: 25 sin t − 20 cos t below the tip, and the clearance.
    EXPECT_NEAR(need, 25.0 * std::sin(t) - 20.0 * std::cos(t) + clearance, 0.05);
    const machine::BuildModel model = machine::make_build_model(m, p, -100.0, -100.0, 100.0, 100.0);
    const Vec3 axis{std::sin(t), 0.0, std::cos(t)};
    const double top = model.substrate.top_z_mm;
    EXPECT_NEAR(machine::head_clearance_mm(model, {0.0, 0.0, top + need}, axis), clearance, 1e-6);
    EXPECT_LT(machine::head_clearance_mm(model, {0.0, 0.0, top + need - 1.0}, axis), clearance);
  }
}

// A travel from one blade's retract to the next blade's approach on a flaring hub: both axes 15°
// below the horizon, 140° apart about +Z. Straight, the A axis would pass −120° on the way and the
// G-code writer refuses the program; turned within the reach it is written, every inserted point
// between the ends and off.
TEST(Reach, ATravelBetweenAxesBelowTheHorizonIsWrittenWithinTheTiltAxis) {
  const machine::MachineConfig m = test::example_machine("ded5_ac");
  const process::ProcessConfig p = test::default_process();
  std::vector<post::ProgramPoint> program;
  program.push_back({{60.0, 0.0, 150.0}, axis_at(105, 0), 8.0, true, 0, 0, "fill"});
  program.push_back({{62.0, 0.0, 150.0}, axis_at(105, 0), 8.0, true, 0, 0, ""});
  program.push_back({{72.0, 0.0, 147.0}, axis_at(105, 0), 50.0, false, 0, 0, "retract"});
  program.push_back({{-55.0, 46.0, 147.0}, axis_at(105, 140), 50.0, false, 1, 1, "approach"});
  program.push_back({{-46.0, 38.0, 150.0}, axis_at(105, 140), 8.0, true, 1, 1, "fill"});
  const auto straight = post::write_gcode(m, p, program);
  ASSERT_FALSE(straight.ok());
  EXPECT_EQ(straight.error().code, core::ErrorCode::kMachineLimit);
  EXPECT_NE(straight.error().message.find(" A-128."), std::string::npos) << straight.error().message;  // past -120° half way
  std::vector<post::ProgramPoint> turned = program;
  keep_travel_within_reach(turned, reach_rad(m));
  ASSERT_GT(turned.size(), program.size() + 50);  // 140° of C about 1° a step
  for (std::size_t i = 3; i + 2 < turned.size(); ++i) {
    EXPECT_FALSE(turned[i].process_on);
    EXPECT_LE(max_tilt_on_arc_rad(turned[i - 1].tool_axis_part, turned[i].tool_axis_part), reach_rad(m) + 1e-9) << i;
  }
  const auto written = post::write_gcode(m, p, turned);
  EXPECT_TRUE(written.ok()) << written.error().message;
  std::vector<post::ProgramPoint> once = turned;  // nothing more to turn
  keep_travel_within_reach(once, reach_rad(m));
  EXPECT_EQ(once.size(), turned.size());
}

}  // namespace
}  // namespace polyaxis::planner::detail
