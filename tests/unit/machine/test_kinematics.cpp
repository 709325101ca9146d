// Forward/inverse kinematics: round trips, branch choice, the singular tilt, C unwrapping, limits,
// and agreement with Dwivedi (2004) §6 Rules 5-9.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "polyaxis/machine/kinematics.h"

namespace polyaxis::machine {
namespace {

using core::ErrorCode;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

MachineConfig five_axis(Kinematics kind, bool conventional) {
  MachineConfig m;
  m.name = "test";
  m.kind = kind;
  m.x_mm = m.y_mm = m.z_mm = {-1e5, 1e5};
  m.tilt_deg = {-180.0, 180.0};
  m.c_continuous = true;
  m.pivot = {12.5, -7.0, 30.0, 0.0, 0.0, -80.0, 15.0, conventional};
  if (kind == Kinematics::kTableTiltA_RotaryC) m.pivot.y_offset_mm = 20.0;
  if (kind == Kinematics::kTableTiltB_RotaryC) m.pivot.x_offset_mm = -25.0;
  if (tilts_head(kind)) m.pivot = TrtPivot{}, m.pivot.pivot_length_mm = 175.0;
  return m;
}

MachineConfig three_axis() {
  MachineConfig m;
  m.name = "g3";
  m.kind = Kinematics::k3Axis;
  m.x_mm = m.y_mm = m.z_mm = {-1e5, 1e5};
  return m;
}

double dist(Vec3 a, Vec3 b) { return norm(a - b); }

void expect_pose_near(const MachinePose& a, const MachinePose& b, double tol) {
  EXPECT_NEAR(a.x_mm, b.x_mm, tol);
  EXPECT_NEAR(a.y_mm, b.y_mm, tol);
  EXPECT_NEAR(a.z_mm, b.z_mm, tol);
  EXPECT_NEAR(a.a_or_b_deg, b.a_or_b_deg, tol);
  EXPECT_NEAR(a.c_deg, b.c_deg, tol);
}

class RoundTrip : public ::testing::TestWithParam<std::pair<Kinematics, bool>> {};

TEST_P(RoundTrip, InverseOfForwardOnRandomPoses) {
  const auto [kind, conventional] = GetParam();
  const MachineConfig m = kind == Kinematics::k3Axis ? three_axis() : five_axis(kind, conventional);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> lin(-300.0, 300.0), tilt(-150.0, 150.0), c(-1000.0, 1000.0);
  for (int i = 0; i < 2000; ++i) {
    MachinePose j{lin(rng), lin(rng), lin(rng), 0.0, 0.0};
    if (has_rotary_axes(kind)) {
      j.a_or_b_deg = tilt(rng);
      j.c_deg = c(rng);
    }
    const MachineToolPose tp = forward(m, j);
    ASSERT_NEAR(norm(tp.tool_axis_part), 1.0, 1e-12);
    // With the pose itself as the previous one, the same branch and turn come back.
    auto same = inverse(m, tp.tip_part_mm, tp.tool_axis_part, &j);
    ASSERT_TRUE(same.ok()) << same.error().message;
    expect_pose_near(same.value(), j, 1e-9);
    // Without a previous pose any branch will do, but it must reproduce tip and axis.
    auto any = inverse(m, tp.tip_part_mm, tp.tool_axis_part, nullptr);
    ASSERT_TRUE(any.ok()) << any.error().message;
    const MachineToolPose back = forward(m, any.value());
    EXPECT_LT(dist(back.tip_part_mm, tp.tip_part_mm), 1e-9);
    EXPECT_LT(dist(back.tool_axis_part, tp.tool_axis_part), 1e-9);
    EXPECT_LE(std::abs(any.value().c_deg), 180.0 + 1e-9);  // no previous: the turn nearest 0
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, RoundTrip,
                         ::testing::Values(std::pair{Kinematics::kTableTiltA_RotaryC, false},
                                           std::pair{Kinematics::kTableTiltA_RotaryC, true},
                                           std::pair{Kinematics::kTableTiltB_RotaryC, false},
                                           std::pair{Kinematics::kTableTiltB_RotaryC, true},
                                           std::pair{Kinematics::kHeadTiltA_RotaryC, false},
                                           std::pair{Kinematics::kHeadTiltB_RotaryC, false},
                                           std::pair{Kinematics::k3Axis, false}));

// LinuxCNC's 5axiskins forward map (the head tilts B about its Y and turns C about Z, the pivot
// pivot_length above the tip), written as it is there: r = s2r(L, C, 180° − B), the spherical
// point of radius L at azimuth C and polar angle 180° − B, and tip = joints + r + (0, 0, L).
Vec3 linuxcnc_5axis_forward(double pivot_length, const MachinePose& j) {
  const double t = j.c_deg * kDeg, p = (180.0 - j.a_or_b_deg) * kDeg;
  const Vec3 r{pivot_length * std::sin(p) * std::cos(t), pivot_length * std::sin(p) * std::sin(t), pivot_length * std::cos(p)};
  return {j.x_mm + r.x, j.y_mm + r.y, j.z_mm + r.z + pivot_length};
}

TEST(Kinematics, HeadBcForwardIsLinuxCnc5AxisKins) {
  const MachineConfig m = five_axis(Kinematics::kHeadTiltB_RotaryC, false);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> lin(-300.0, 300.0), tilt(-120.0, 120.0), c(-720.0, 720.0);
  for (int i = 0; i < 500; ++i) {
    const MachinePose j{lin(rng), lin(rng), lin(rng), tilt(rng), c(rng)};
    const MachineToolPose tp = forward(m, j);
    EXPECT_LT(dist(tp.tip_part_mm, linuxcnc_5axis_forward(m.pivot.pivot_length_mm, j)), 1e-9);
    // The tool axis runs from the tip to the pivot, which stays where the joints put it.
    const Vec3 pivot{j.x_mm, j.y_mm, j.z_mm + m.pivot.pivot_length_mm};
    EXPECT_LT(dist(tp.tip_part_mm + tp.tool_axis_part * m.pivot.pivot_length_mm, pivot), 1e-9);
  }
  // B = 90° at C = 0 lays the tool along −X: the tip swings out to +X of the pivot.
  const MachineToolPose side = forward(m, {0.0, 0.0, 0.0, 90.0, 0.0});
  EXPECT_LT(dist(side.tool_axis_part, {-1.0, 0.0, 0.0}), 1e-12);
  EXPECT_LT(dist(side.tip_part_mm, {175.0, 0.0, 175.0}), 1e-9);
}

TEST(Kinematics, HeadAcTiltsAboutItsX) {
  const MachineConfig m = five_axis(Kinematics::kHeadTiltA_RotaryC, false);
  // A = 90° at C = 0: the axis Rx(90°)·ẑ = −Y; at C = 90° it is turned to +X.
  EXPECT_LT(dist(forward(m, {0, 0, 0, 90.0, 0.0}).tool_axis_part, {0.0, -1.0, 0.0}), 1e-12);
  EXPECT_LT(dist(forward(m, {0, 0, 0, 90.0, 90.0}).tool_axis_part, {1.0, 0.0, 0.0}), 1e-12);
  // The part does not move: the tip is the joints plus the pivot's swing, whatever C.
  const MachineToolPose tp = forward(m, {10.0, 20.0, 30.0, 30.0, 45.0});
  EXPECT_LT(dist(tp.tip_part_mm, Vec3{10.0, 20.0, 30.0} + (Vec3{0, 0, 1} - tp.tool_axis_part) * 175.0), 1e-9);
}

// LinuxCNC 2.9's xyzac-trt-kins forward map (trtfuncs.c, before the conventional-directions pin),
// written out term by term as it is there, with joints (x, y, z, a, c).
Vec3 linuxcnc_xyzac_forward(const TrtPivot& p, const MachinePose& j) {
  const double a = j.a_or_b_deg * kDeg, c = j.c_deg * kDeg;
  const double dy = p.y_offset_mm, dz = p.z_offset_mm + p.tool_offset_mm;
  const double xr = p.x_rot_point_mm, yr = p.y_rot_point_mm, zr = p.z_rot_point_mm;
  return {std::cos(c) * (j.x_mm - xr) + std::sin(c) * std::cos(a) * (j.y_mm - dy - yr) +
              std::sin(c) * std::sin(a) * (j.z_mm - dz - zr) + std::sin(c) * dy + xr,
          -std::sin(c) * (j.x_mm - xr) + std::cos(c) * std::cos(a) * (j.y_mm - dy - yr) +
              std::cos(c) * std::sin(a) * (j.z_mm - dz - zr) + std::cos(c) * dy + yr,
          -std::sin(a) * (j.y_mm - dy - yr) + std::cos(a) * (j.z_mm - dz - zr) + dz + zr};
}

Vec3 linuxcnc_xyzbc_forward(const TrtPivot& p, const MachinePose& j) {
  const double b = j.a_or_b_deg * kDeg, c = j.c_deg * kDeg;
  const double dx = p.x_offset_mm, dz = p.z_offset_mm + p.tool_offset_mm;
  const double xr = p.x_rot_point_mm, yr = p.y_rot_point_mm, zr = p.z_rot_point_mm;
  return {std::cos(c) * std::cos(b) * (j.x_mm - dx - xr) + std::sin(c) * (j.y_mm - yr) -
              std::cos(c) * std::sin(b) * (j.z_mm - dz - zr) + std::cos(c) * dx + xr,
          -std::sin(c) * std::cos(b) * (j.x_mm - dx - xr) + std::cos(c) * (j.y_mm - yr) +
              std::sin(c) * std::sin(b) * (j.z_mm - dz - zr) - std::sin(c) * dx + yr,
          std::sin(b) * (j.x_mm - dx - xr) + std::cos(b) * (j.z_mm - dz - zr) + dz + zr};
}

TEST(Kinematics, ForwardIsLinuxCncTrtKins) {
  const MachineConfig ac = five_axis(Kinematics::kTableTiltA_RotaryC, false);
  const MachineConfig bc = five_axis(Kinematics::kTableTiltB_RotaryC, false);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> lin(-300.0, 300.0), ang(-360.0, 360.0);
  for (int i = 0; i < 500; ++i) {
    const MachinePose j{lin(rng), lin(rng), lin(rng), ang(rng), ang(rng)};
    EXPECT_LT(dist(forward(ac, j).tip_part_mm, linuxcnc_xyzac_forward(ac.pivot, j)), 1e-9);
    EXPECT_LT(dist(forward(bc, j).tip_part_mm, linuxcnc_xyzbc_forward(bc.pivot, j)), 1e-9);
  }
}

// Dwivedi, Zekovic, Kovacevic (2004) §6, platform of Fig. 5: a table that rotates about a vertical
// axis and tilts about a horizontal one, with the substrate point at offsets r and h from the
// rotation centre. The paper's formulas, as printed:
//   Rule 5: e = (0, 0, 1) is vertical.
//   Rule 6: θ = ArcTan(e2/e3), φ = ArcTan(e1/e2).
//   Rule 7: rotating by the Rule-6 angles makes the layer vertical.
//   Rule 8: Δx = r·cosθ·cosφ + h·sinφ, Δy = r·sinθ, Δz = r·cosθ·sinφ − h·cosφ.
//   Rule 9: rotate θ, rotate φ, then translate Δx, Δy, Δz.
// Sign conventions. Read literally, Rules 6 and 8 use θ and φ for different axes: in Rule 8,
// Δ = Ry(−φ)·Rz(θ)·(r, 0, −h), i.e. θ turns about the vertical axis and φ tilts about Y, and Δ is
// where the offset (r, 0, −h) (Δ at θ = φ = 0) ends up; in Rule 6, φ = ArcTan(e1/e2) is the turn
// about the vertical axis that brings e into the Y-Z plane and θ the tilt about X that then makes
// it vertical (θ = ArcTan(e2/e3) exactly when e1 = 0; in general e2 is the component after the φ
// turn, sign(e2)·hypot(e1, e2)). So Rule 6 is checked on an A/C table and Rule 8 on a B/C table,
// both in LinuxCNC 2.9's rotation sense (conventional_directions = false). Rule 9's order does not
// change the final pose: the translation is applied after both rotations.
TEST(Kinematics, DwivediRules5To7OrientationAngles) {
  MachineConfig m = five_axis(Kinematics::kTableTiltA_RotaryC, false);
  // Rule 5: vertical needs no tilt.
  auto v = inverse(m, {1.0, 2.0, 3.0}, {0.0, 0.0, 1.0}, nullptr);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(v.value().a_or_b_deg, 0.0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> comp(-1.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const Vec3 e = normalized(Vec3{comp(rng), comp(rng), 0.2 + std::abs(comp(rng))});
    if (std::abs(e.y) < 1e-3) continue;
    auto pose = inverse(m, {0.0, 0.0, 0.0}, e, nullptr);
    ASSERT_TRUE(pose.ok());
    const double phi = std::atan(e.x / e.y);                          // Rule 6, φ
    const double theta = std::atan(std::copysign(std::hypot(e.x, e.y), e.y) / e.z);  // Rule 6, θ after the φ turn
    // C is φ up to a half turn (which branch the IK takes); |A| is |θ|.
    EXPECT_NEAR(std::remainder(pose.value().c_deg * kDeg - phi, kPi), 0.0, 1e-9);
    EXPECT_NEAR(std::abs(pose.value().a_or_b_deg * kDeg), std::abs(theta), 1e-9);
    // Rule 7: the part's tool axis, turned by the table, is the machine's vertical.
    const double a = -pose.value().a_or_b_deg * kDeg, c = -pose.value().c_deg * kDeg;  // s = −1
    const Vec3 turned{std::cos(-c) * e.x - std::sin(-c) * e.y, std::sin(-c) * e.x + std::cos(-c) * e.y, e.z};
    const Vec3 vertical{turned.x, std::cos(-a) * turned.y - std::sin(-a) * turned.z,
                        std::sin(-a) * turned.y + std::cos(-a) * turned.z};
    EXPECT_LT(dist(vertical, {0.0, 0.0, 1.0}), 1e-9);
  }
  // With e1 = 0 Rule 6 holds as printed: θ = ArcTan(e2/e3).
  const Vec3 e{0.0, 0.5, 0.8};
  auto pose = inverse(m, {0.0, 0.0, 0.0}, e, nullptr);
  ASSERT_TRUE(pose.ok());
  EXPECT_NEAR(std::abs(pose.value().a_or_b_deg * kDeg), std::atan(e.y / e.z), 1e-12);
}

TEST(Kinematics, DwivediRules8And9CompensatingTranslation) {
  MachineConfig m = five_axis(Kinematics::kTableTiltB_RotaryC, false);
  m.pivot.x_offset_mm = m.pivot.z_offset_mm = m.pivot.tool_offset_mm = 0.0;  // both axes through the pivot
  const Vec3 pivot{m.pivot.x_rot_point_mm, m.pivot.y_rot_point_mm, m.pivot.z_rot_point_mm};
  const double r = 35.0, h = 12.0;
  auto delta = [&](double theta, double phi) {  // Rule 8 as printed
    return Vec3{r * std::cos(theta) * std::cos(phi) + h * std::sin(phi), r * std::sin(theta),
                r * std::cos(theta) * std::sin(phi) - h * std::cos(phi)};
  };
  const Vec3 substrate = pivot + delta(0.0, 0.0);  // the point at offsets r, h before any rotation
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> ang(-80.0 * kDeg, 80.0 * kDeg);
  for (int i = 0; i < 500; ++i) {
    const double theta = ang(rng), phi = ang(rng);
    if (std::abs(phi) < 1e-3) continue;  // keep away from the singular tilt, where C is held
    // Paper angles in machine words (s = −1): C = θ, B = −φ.
    const MachinePose hint{0.0, 0.0, 0.0, -phi / kDeg, theta / kDeg};
    const Vec3 axis = forward(m, hint).tool_axis_part;
    auto pose = inverse(m, substrate, axis, &hint);
    ASSERT_TRUE(pose.ok()) << pose.error().message;
    EXPECT_NEAR(pose.value().c_deg, theta / kDeg, 1e-9);
    EXPECT_NEAR(pose.value().a_or_b_deg, -phi / kDeg, 1e-9);
    // Rule 8/9: after both rotations the linear axes move by Δ(θ, φ) − Δ(0, 0).
    const Vec3 moved = Vec3{pose.value().x_mm, pose.value().y_mm, pose.value().z_mm} - substrate;
    EXPECT_LT(dist(moved, delta(theta, phi) - delta(0.0, 0.0)), 1e-9);
  }
}

TEST(Kinematics, SingularTiltHoldsC) {
  for (const Kinematics kind : {Kinematics::kTableTiltA_RotaryC, Kinematics::kTableTiltB_RotaryC, Kinematics::kHeadTiltA_RotaryC,
                                Kinematics::kHeadTiltB_RotaryC}) {
    const MachineConfig m = five_axis(kind, false);
    MachinePose prev{0.0, 0.0, 0.0, 10.0, 123.0};
    // Tiny tilts in every direction, and exactly vertical: C stays at 123°.
    for (int k = 0; k < 36; ++k) {
      const double az = k * 10.0 * kDeg, tilt = (k % 3 == 0) ? 0.0 : 1e-8 * k;
      const Vec3 axis{std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt)};
      auto pose = inverse(m, {5.0, 6.0, 7.0}, axis, &prev);
      ASSERT_TRUE(pose.ok());
      EXPECT_EQ(pose.value().c_deg, 123.0);
      // The tip still lands exactly; the axis is off by at most the singular tolerance.
      const MachineToolPose tp = forward(m, pose.value());
      EXPECT_LT(dist(tp.tip_part_mm, {5.0, 6.0, 7.0}), 1e-9);
      EXPECT_LT(std::acos(std::min(1.0, dot(tp.tool_axis_part, axis))), kSingularTiltRad);
      prev = pose.value();
    }
  }
}

TEST(Kinematics, UpsideDownToolTakesTheHalfTurnNearestThePreviousTilt) {
  // With the tool along −Z the tilt is ±180°, the same orientation: the one next to the previous
  // tilt is taken, so the table does not swing a full turn between them. C is held.
  for (const Kinematics kind : {Kinematics::kTableTiltA_RotaryC, Kinematics::kTableTiltB_RotaryC, Kinematics::kHeadTiltA_RotaryC,
                                Kinematics::kHeadTiltB_RotaryC}) {
    const MachineConfig m = five_axis(kind, false);
    for (const double prev_tilt : {-170.0, 170.0}) {
      const MachinePose prev{0.0, 0.0, 0.0, prev_tilt, 37.0};
      auto pose = inverse(m, {5.0, 6.0, 7.0}, {0.0, 0.0, -1.0}, &prev);
      ASSERT_TRUE(pose.ok()) << pose.error().message;
      EXPECT_NEAR(pose.value().a_or_b_deg, std::copysign(180.0, prev_tilt), 1e-9);
      EXPECT_EQ(pose.value().c_deg, 37.0);
      EXPECT_LT(dist(forward(m, pose.value()).tip_part_mm, {5.0, 6.0, 7.0}), 1e-9);
    }
  }
}

TEST(Kinematics, CUnwrapsAcrossPlusMinus180) {
  for (const Kinematics kind : {Kinematics::kTableTiltA_RotaryC, Kinematics::kTableTiltB_RotaryC}) {
    const MachineConfig m = five_axis(kind, false);
    MachinePose prev{};
    bool first = true;
    // The tool axis circles twice at 30° tilt: C must change by 10° per step, never jump by 360°.
    for (int k = 0; k <= 72; ++k) {
      const double az = k * 10.0 * kDeg;
      const Vec3 axis{std::sin(30.0 * kDeg) * std::cos(az), std::sin(30.0 * kDeg) * std::sin(az), std::cos(30.0 * kDeg)};
      auto pose = inverse(m, {50.0, 0.0, 10.0}, axis, first ? nullptr : &prev);
      ASSERT_TRUE(pose.ok());
      if (!first) {
        EXPECT_NEAR(std::abs(pose.value().c_deg - prev.c_deg), 10.0, 1e-9) << k;
        EXPECT_NEAR(pose.value().a_or_b_deg, prev.a_or_b_deg, 1e-9) << k;
      }
      prev = pose.value();
      first = false;
    }
    EXPECT_GT(std::abs(prev.c_deg), 540.0);  // two full turns accumulated
  }
}

TEST(Kinematics, CWithEndStopsTakesTheTurnInsideTheRange) {
  MachineConfig m = five_axis(Kinematics::kTableTiltA_RotaryC, false);
  m.c_continuous = false;
  m.c_deg = {-400.0, 400.0};
  const MachinePose prev{0.0, 0.0, 0.0, 30.0, 390.0};
  // Continuing the turn would need C = 420°. The least motion inside the range is the other
  // branch: A = −30°, C = 240° (60° + 150° of rotary motion, against 330° for C = 60°).
  const Vec3 axis = forward(m, MachinePose{0.0, 0.0, 0.0, 30.0, 420.0}).tool_axis_part;
  auto pose = inverse(m, {0.0, 0.0, 0.0}, axis, &prev);
  ASSERT_TRUE(pose.ok()) << pose.error().message;
  EXPECT_NEAR(pose.value().a_or_b_deg, -30.0, 1e-9);
  EXPECT_NEAR(pose.value().c_deg, 240.0, 1e-9);
  // Without negative tilts, the turn back to C = 60° is the only solution.
  m.tilt_deg = {0.0, 120.0};
  auto unwound = inverse(m, {0.0, 0.0, 0.0}, axis, &prev);
  ASSERT_TRUE(unwound.ok()) << unwound.error().message;
  EXPECT_NEAR(unwound.value().a_or_b_deg, 30.0, 1e-9);
  EXPECT_NEAR(unwound.value().c_deg, 60.0, 1e-9);
}

TEST(Kinematics, BranchWithLeastRotaryMotion) {
  const MachineConfig m = five_axis(Kinematics::kTableTiltA_RotaryC, false);
  const Vec3 axis = forward(m, MachinePose{0.0, 0.0, 0.0, 20.0, 40.0}).tool_axis_part;
  const MachinePose near_neg{0.0, 0.0, 0.0, -25.0, 215.0};
  auto pose = inverse(m, {0.0, 0.0, 0.0}, axis, &near_neg);
  ASSERT_TRUE(pose.ok());
  EXPECT_NEAR(pose.value().a_or_b_deg, -20.0, 1e-9);
  EXPECT_NEAR(pose.value().c_deg, 220.0, 1e-9);
}

TEST(Kinematics, LimitsNameAxisValueAndLimit) {
  MachineConfig m = five_axis(Kinematics::kTableTiltA_RotaryC, false);
  m.tilt_deg = {-30.0, 120.0};
  // 60° tilt: +60 fits; −60 (the other branch) does not, so the IK takes +60 whatever the previous.
  const MachinePose prev{0.0, 0.0, 0.0, -50.0, 180.0};
  const Vec3 axis60 = forward(m, MachinePose{0.0, 0.0, 0.0, 60.0, 0.0}).tool_axis_part;
  auto ok = inverse(m, {0.0, 0.0, 0.0}, axis60, &prev);
  ASSERT_TRUE(ok.ok());
  EXPECT_NEAR(ok.value().a_or_b_deg, 60.0, 1e-9);
  // 130°: both branches (±130°) are beyond the A range.
  const Vec3 axis130 = forward(m, MachinePose{0.0, 0.0, 0.0, 130.0, 0.0}).tool_axis_part;
  auto bad = inverse(m, {0.0, 0.0, 0.0}, axis130, nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kMachineLimit);
  EXPECT_NE(bad.error().message.find("A = "), std::string::npos) << bad.error().message;
  EXPECT_NE(bad.error().message.find("130.0000"), std::string::npos) << bad.error().message;
  EXPECT_NE(bad.error().message.find("120"), std::string::npos) << bad.error().message;
  // A linear axis beyond its range.
  m.z_mm = {-100.0, 100.0};
  auto z = inverse(m, {0.0, 0.0, 500.0}, {0.0, 0.0, 1.0}, nullptr);
  ASSERT_FALSE(z.ok());
  EXPECT_NE(z.error().message.find("Z = "), std::string::npos) << z.error().message;
  EXPECT_NE(z.error().message.find("maximum 100"), std::string::npos) << z.error().message;
}

// reachable() answers what inverse() would, on every kind, with limits that cut through the
// sampled poses (so that both answers occur), on random tips and axes and on bad input.
TEST(Kinematics, ReachableAgreesWithInverse) {
  const std::pair<Kinematics, bool> kinds[] = {{Kinematics::kTableTiltA_RotaryC, false}, {Kinematics::kTableTiltB_RotaryC, true},
                                               {Kinematics::kHeadTiltA_RotaryC, false}, {Kinematics::kHeadTiltB_RotaryC, false},
                                               {Kinematics::k3Axis, false}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> lin(-200.0, 200.0), unit(-1.0, 1.0);
  int yes = 0, no = 0;
  for (const auto& [kind, conventional] : kinds) {
    MachineConfig m = kind == Kinematics::k3Axis ? three_axis() : five_axis(kind, conventional);
    m.x_mm = {-150.0, 120.0}, m.z_mm = {-90.0, 160.0};
    if (has_rotary_axes(kind)) m.tilt_deg = {-40.0, 100.0}, m.c_continuous = false, m.c_deg = {-200.0, 150.0};
    for (int i = 0; i < 3000; ++i) {
      const Vec3 tip{lin(rng), lin(rng), lin(rng)};
      Vec3 axis{unit(rng), unit(rng), unit(rng)};
      if (kind == Kinematics::k3Axis && i % 2 == 0) axis = {0.0, 0.0, 1.0 + unit(rng)};
      const bool expected = inverse(m, tip, axis, nullptr).ok();
      ASSERT_EQ(reachable(m, tip, axis), expected) << static_cast<int>(kind) << " tip " << tip.x << " " << tip.y << " " << tip.z;
      (expected ? yes : no) += 1;
    }
    EXPECT_FALSE(reachable(m, {NAN, 0.0, 0.0}, {0.0, 0.0, 1.0}));
    EXPECT_FALSE(reachable(m, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}));
  }
  EXPECT_GT(yes, 1000);
  EXPECT_GT(no, 1000);
}

TEST(Kinematics, ThreeAxisRefusesTilt) {
  const MachineConfig m = three_axis();
  auto bad = inverse(m, {0.0, 0.0, 0.0}, {0.0, 0.1, 1.0}, nullptr);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, ErrorCode::kMachineLimit);
  auto nan = inverse(m, {NAN, 0.0, 0.0}, {0.0, 0.0, 1.0}, nullptr);
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().code, ErrorCode::kInternal);
}

}  // namespace
}  // namespace polyaxis::machine
