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
  // The robot cell's slim torch (a circle of 12 mm at 40 mm up the axis) pointing out over the
  // plate's edge 5.45 mm above it: horizontal, that circle just misses the plate (the table is
  // 10 mm lower); tilted up 10 degrees it clears the plate; half way it swings over the plate's
  // edge while still low: the move between two clear poses is not clear (cyl_walls5's wall roots).
  machine::BuildModel model;
  model.nozzle = test::example_machine("robot_abb_positioner").nozzle;
  model.substrate = {-50.0, -50.0, 50.0, 50.0, 0.0, 10.0};
  const Vec3 tip{0.0, -50.0 - 12.0 - 0.1 + 40.0, 5.45};
  const Vec3 level{0.0, -1.0, 0.0}, up10{0.0, -std::cos(10.0 * kDeg), std::sin(10.0 * kDeg)};
  EXPECT_GT(machine::head_clearance_mm(model, tip, level), 0.0);
  EXPECT_GT(machine::head_clearance_mm(model, tip, up10), 0.0);
  EXPECT_FALSE(move_clear(model, 0.0, tip, up10, tip, level));
  EXPECT_TRUE(move_clear(model, 0.0, tip, up10, tip, up10));
  // Moving up while it turns, the head stays clear.
  EXPECT_TRUE(move_clear(model, 0.0, tip, up10, tip + Vec3{0.0, 0.0, 40.0}, level));
}

}  // namespace
}  // namespace polyaxis::planner::detail
