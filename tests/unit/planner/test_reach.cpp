// Which build directions a machine can take (planner/reach.h): a table-table machine turns any
// direction within its tilt reach up; a head-head machine leaves the part fixed, so a region may
// lean only as far off vertical as the process deposits (off_vertical_max_deg), and a region
// beyond is refused naming that key rather than the tilt axis.
#include <gtest/gtest.h>

#include <cmath>

#include "planner/reach.h"
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

}  // namespace
}  // namespace polyaxis::planner::detail
