#include "polyaxis/mesh/tube.h"

#include <cmath>
#include <numbers>

#include "polyaxis/mesh/properties.h"

namespace polyaxis::mesh {

namespace {

// A unit vector normal to unit T.
Vec3 any_normal(Vec3 t) {
  const Vec3 a = std::fabs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return core::normalized(core::cross(t, a));
}

}  // namespace

Mesh tube(const std::vector<Vec3>& axis, const std::vector<double>& radii, int sides, int quarter_rings) {
  const std::size_t n = axis.size();
  std::vector<Vec3> tangent(n);
  for (std::size_t i = 0; i < n; ++i) {
    tangent[i] = core::normalized(axis[std::min(i + 1, n - 1)] - axis[i > 0 ? i - 1 : 0]);
  }
  // Frames by parallel transport: each normal is the one before less its part along the tangent.
  std::vector<Vec3> normal(n);
  normal[0] = any_normal(tangent[0]);
  for (std::size_t i = 1; i < n; ++i) {
    const Vec3 carried = normal[i - 1] - tangent[i] * core::dot(normal[i - 1], tangent[i]);
    normal[i] = core::norm(carried) > 1e-9 ? core::normalized(carried) : any_normal(tangent[i]);
  }
  Mesh m;
  const auto ring_size = static_cast<std::uint32_t>(sides);
  auto add_ring = [&](Vec3 centre, Vec3 t, Vec3 u, double r) {
    const Vec3 v = core::cross(t, u);
    for (int k = 0; k < sides; ++k) {
      const double a = 2.0 * std::numbers::pi * k / sides;
      m.vertices.push_back(centre + (u * std::cos(a) + v * std::sin(a)) * r);
    }
  };
  // Rings: the start cap's (from the pole outwards), the axis's, the end cap's (inwards).
  const Vec3 start_pole = axis.front() - tangent.front() * radii.front();
  m.vertices.push_back(start_pole);
  for (int j = 1; j < quarter_rings; ++j) {
    const double phi = 0.5 * std::numbers::pi * j / quarter_rings;  // from the pole
    add_ring(axis.front() - tangent.front() * (radii.front() * std::cos(phi)), tangent.front(), normal.front(), radii.front() * std::sin(phi));
  }
  for (std::size_t i = 0; i < n; ++i) add_ring(axis[i], tangent[i], normal[i], radii[i]);
  for (int j = quarter_rings - 1; j >= 1; --j) {
    const double phi = 0.5 * std::numbers::pi * j / quarter_rings;
    add_ring(axis.back() + tangent.back() * (radii.back() * std::cos(phi)), tangent.back(), normal.back(), radii.back() * std::sin(phi));
  }
  m.vertices.push_back(axis.back() + tangent.back() * radii.back());
  const auto rings = static_cast<std::uint32_t>(n) + 2u * static_cast<std::uint32_t>(quarter_rings - 1);
  const std::uint32_t first = 1, end_pole = static_cast<std::uint32_t>(m.vertices.size()) - 1;
  for (std::uint32_t k = 0; k < ring_size; ++k) {
    const std::uint32_t k1 = (k + 1) % ring_size;
    m.triangles.push_back({0, first + k1, first + k});
    for (std::uint32_t r = 0; r + 1 < rings; ++r) {
      const std::uint32_t a = first + r * ring_size, b = a + ring_size;
      m.triangles.push_back({a + k, a + k1, b + k1});
      m.triangles.push_back({a + k, b + k1, b + k});
    }
    const std::uint32_t last = first + (rings - 1) * ring_size;
    m.triangles.push_back({end_pole, last + k, last + k1});
  }
  if (signed_volume(m) < 0.0) {
    for (io::Triangle& t : m.triangles) std::swap(t[1], t[2]);
  }
  return m;
}

}  // namespace polyaxis::mesh
