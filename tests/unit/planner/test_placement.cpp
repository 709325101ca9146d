// The placement turns the build direction to the table's +Z with a proper rotation.
#include <gtest/gtest.h>

#include <cmath>

#include "polyaxis/planner/plan.h"

namespace polyaxis::planner {
namespace {

TEST(Placement, TurnsTheBuildDirectionUpWithAProperRotation) {
  for (const Vec3 d : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0.3, -0.4, 0.5},
                       Vec3{1e-9, 0, -1}, Vec3{-0.57, 0.0, 0.82}}) {
    const Placement p = rotation_to_z(d);
    const Vec3 up = p.rotate(core::normalized(d));
    EXPECT_NEAR(up.x, 0.0, 1e-12);
    EXPECT_NEAR(up.y, 0.0, 1e-12);
    EXPECT_NEAR(up.z, 1.0, 1e-12);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(core::dot(p.rows[i], p.rows[j]), i == j ? 1.0 : 0.0, 1e-12);
    }
    EXPECT_NEAR(core::dot(core::cross(p.rows[0], p.rows[1]), p.rows[2]), 1.0, 1e-12);  // not a mirror
    const Vec3 q{3, -2, 7};
    const Vec3 back = p.unrotate(p.rotate(q));
    EXPECT_NEAR(core::norm(back - q), 0.0, 1e-12);
  }
  // +Z needs no turn.
  const Placement id = rotation_to_z({0, 0, 2});
  EXPECT_EQ(id.rotate({1, 2, 3}).x, 1.0);
}

}  // namespace
}  // namespace polyaxis::planner
