// The tool's frame of the 3MF toolpath's <point6d>: a unit quaternion (i, j, k, w) turning the
// machine's axes onto the tool's, whose local z is the tool axis (the spec's §1.4.2 formulas).
#pragma once

#include <cmath>

#include "polyaxis/core/vec3.h"

namespace polyaxis::post::detail {

struct Quaternion {
  double i = 0.0, j = 0.0, k = 0.0, w = 1.0;
};

inline Quaternion normalized(Quaternion q) {
  const double n = std::sqrt(q.i * q.i + q.j * q.j + q.k * q.k + q.w * q.w);
  return n > 0.0 ? Quaternion{q.i / n, q.j / n, q.k / n, q.w / n} : Quaternion{};
}

// A · B (B first, then A).
inline Quaternion multiply(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.i + a.i * b.w + a.j * b.k - a.k * b.j, a.w * b.j - a.i * b.k + a.j * b.w + a.k * b.i,
          a.w * b.k + a.i * b.j - a.j * b.i + a.k * b.w, a.w * b.w - a.i * b.i - a.j * b.j - a.k * b.k};
}

// The frame's local z: the third column of the rotation matrix.
inline core::Vec3 z_axis(const Quaternion& q) {
  return {2.0 * (q.i * q.k + q.j * q.w), 2.0 * (q.j * q.k - q.i * q.w), 1.0 - 2.0 * (q.i * q.i + q.j * q.j)};
}

// The smallest rotation turning unit A onto unit B (about A × B; a half turn about an axis
// normal to A when they are opposite).
inline Quaternion rotation_between(core::Vec3 a, core::Vec3 b) {
  const double d = core::dot(a, b);
  if (d < -1.0 + 1e-12) {
    const core::Vec3 n = core::normalized(std::abs(a.x) < 0.9 ? core::cross(a, core::Vec3{1, 0, 0}) : core::cross(a, core::Vec3{0, 1, 0}));
    return {n.x, n.y, n.z, 0.0};
  }
  const core::Vec3 c = core::cross(a, b);
  return normalized(Quaternion{c.x, c.y, c.z, 1.0 + d});
}

// The frame whose z is unit AXIS, turned from the machine's axes by the smallest rotation.
inline Quaternion frame_from_z(core::Vec3 axis) { return rotation_between(core::Vec3{0, 0, 1}, core::normalized(axis)); }

// FRAME carried to unit AXIS by the smallest rotation of its z (no twist about the tool): nlerp
// between the two then turns z along the great circle.
inline Quaternion carry_frame(const Quaternion& frame, core::Vec3 axis) {
  return normalized(multiply(rotation_between(core::normalized(z_axis(frame)), core::normalized(axis)), frame));
}

}  // namespace polyaxis::post::detail
