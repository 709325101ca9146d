// Test meshes made in code, served by kind so a property can be checked on all of them.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::test {

using io::RawMesh;

// Axis-aligned box [lo, hi], outward, 8 vertices, 12 triangles.
inline RawMesh box(core::Vec3 lo, core::Vec3 hi) {
  RawMesh m;
  for (int i = 0; i < 8; ++i) m.points.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& f : q) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

inline RawMesh cube(double size = 10.0) { return box({0, 0, 0}, {size, size, size}); }

// Torus around Z: major radius R, minor r, n×m quads split in two; volume 2π²Rr² in the limit.
inline RawMesh torus(double major, double minor, std::uint32_t n, std::uint32_t m) {
  RawMesh mesh;
  const double two_pi = 2.0 * 3.14159265358979323846;
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < m; ++j) {
      const double u = two_pi * i / n, v = two_pi * j / m;
      mesh.points.push_back({(major + minor * std::cos(v)) * std::cos(u), (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v)});
    }
  }
  auto id = [&](std::uint32_t i, std::uint32_t j) { return (i % n) * m + (j % m); };
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < m; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return mesh;
}

// A solid frustum about Z from radius R0 at z = 0 to R1 at z = H, N sides; a flared cup when
// R1 > R0 (its side overhangs by atan((R1 − R0)/H) from vertical all the way round).
inline RawMesh frustum(double r0, double r1, double h, std::uint32_t n) {
  RawMesh mesh;
  const double two_pi = 2.0 * 3.14159265358979323846;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double u = two_pi * i / n;
    mesh.points.push_back({r0 * std::cos(u), r0 * std::sin(u), 0.0});
    mesh.points.push_back({r1 * std::cos(u), r1 * std::sin(u), h});
  }
  const auto bottom = static_cast<std::uint32_t>(mesh.points.size());
  mesh.points.push_back({0.0, 0.0, 0.0});
  mesh.points.push_back({0.0, 0.0, h});
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = 2 * i, b = 2 * ((i + 1) % n);
    mesh.triangles.push_back({a, b, b + 1});
    mesh.triangles.push_back({a, b + 1, a + 1});
    mesh.triangles.push_back({bottom, b, a});
    mesh.triangles.push_back({bottom + 1, a + 1, b + 1});
  }
  return mesh;
}

// Signed volume of A (divergence theorem), mm³: positive when A is closed and outward.
inline double signed_volume_of(const RawMesh& a) {
  double v = 0.0;
  for (const auto& t : a.triangles) {
    const auto& p = a.points[t[0]];
    const auto& q = a.points[t[1]];
    const auto& r = a.points[t[2]];
    v += (p.x * (q.y * r.z - q.z * r.y) - p.y * (q.x * r.z - q.z * r.x) + p.z * (q.x * r.y - q.y * r.x)) / 6.0;
  }
  return v;
}

// A round bar of radius R_BAR bent along an arc of radius R_BEND through SWEEP_DEG, standing on
// z = 0 (its first end) and bending from +Z towards +X; N segments along the arc, M around the bar,
// both ends capped. Closed and outward.
inline RawMesh bent_bar(double r_bend, double r_bar, double sweep_deg, std::uint32_t n, std::uint32_t m) {
  RawMesh mesh;
  const double kPi = 3.14159265358979323846;
  for (std::uint32_t i = 0; i <= n; ++i) {
    const double phi = sweep_deg * kPi / 180.0 * i / n;
    const core::Vec3 c{r_bend - r_bend * std::cos(phi), 0.0, r_bend * std::sin(phi)};
    const core::Vec3 nrm{std::cos(phi), 0.0, -std::sin(phi)};
    for (std::uint32_t j = 0; j < m; ++j) {
      const double th = 2.0 * kPi * j / m;
      mesh.points.push_back({c.x + r_bar * std::cos(th) * nrm.x, r_bar * std::sin(th), c.z + r_bar * std::cos(th) * nrm.z});
    }
  }
  auto id = [&](std::uint32_t i, std::uint32_t j) { return i * m + (j % m); };
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < m; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  for (const std::uint32_t i : {0u, n}) {  // caps: fans round the ends' centres
    core::Vec3 c{0, 0, 0};
    for (std::uint32_t j = 0; j < m; ++j) c = c + core::Vec3{mesh.points[id(i, j)].x, mesh.points[id(i, j)].y, mesh.points[id(i, j)].z};
    c = c / static_cast<double>(m);
    const auto centre = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.push_back({c.x, c.y, c.z});
    for (std::uint32_t j = 0; j < m; ++j) {
      if (i == 0) mesh.triangles.push_back({centre, id(i, j + 1), id(i, j)});
      else mesh.triangles.push_back({centre, id(i, j), id(i, j + 1)});
    }
  }
  if (signed_volume_of(mesh) < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

// A prism: the simple polygon OUTLINE (x, z pairs, either winding) in the XZ plane, extruded
// along Y from 0 to WIDTH. Ear clipping for the two faces. Closed and outward.
inline RawMesh prism_xz(const std::vector<std::array<double, 2>>& outline, double width) {
  RawMesh mesh;
  const auto n = static_cast<std::uint32_t>(outline.size());
  for (const double y : {0.0, width}) {
    for (const auto& p : outline) mesh.points.push_back({p[0], y, p[1]});
  }
  double area = 0.0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto& a = outline[i];
    const auto& b = outline[(i + 1) % n];
    area += a[0] * b[1] - b[0] * a[1];
  }
  const double sgn = area > 0.0 ? 1.0 : -1.0;
  auto cross = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return sgn * ((outline[b][0] - outline[a][0]) * (outline[c][1] - outline[a][1]) -
                  (outline[b][1] - outline[a][1]) * (outline[c][0] - outline[a][0]));
  };
  std::vector<std::uint32_t> left(n);
  for (std::uint32_t i = 0; i < n; ++i) left[i] = i;
  std::vector<std::array<std::uint32_t, 3>> ears;
  while (left.size() > 3) {
    bool cut = false;
    for (std::size_t k = 0; k < left.size() && !cut; ++k) {
      const std::uint32_t a = left[(k + left.size() - 1) % left.size()], b = left[k], c = left[(k + 1) % left.size()];
      if (cross(a, b, c) <= 0.0) continue;
      bool inside = false;
      for (const std::uint32_t q : left) {
        if (q == a || q == b || q == c) continue;
        inside = inside || (cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0);
      }
      if (inside) continue;
      ears.push_back({a, b, c});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(k));
      cut = true;
    }
    if (!cut) break;
  }
  ears.push_back({left[0], left[1], left[2]});
  for (const auto& e : ears) {
    mesh.triangles.push_back({e[0], e[1], e[2]});          // y = 0
    mesh.triangles.push_back({e[0] + n, e[2] + n, e[1] + n});  // y = width
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({i, j, j + n});
    mesh.triangles.push_back({i, j + n, i + n});
  }
  if (signed_volume_of(mesh) < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

// A closed cylinder of radius R from BASE along AXIS (any length > 0) for LENGTH mm, N sides.
inline RawMesh cylinder(core::Vec3 base, core::Vec3 axis, double r, double length, std::uint32_t n) {
  const core::Vec3 a = core::normalized(axis);
  const core::Vec3 helper = std::abs(a.x) < 0.9 ? core::Vec3{1, 0, 0} : core::Vec3{0, 1, 0};
  const core::Vec3 u = core::normalized(core::cross(a, helper)), v = core::cross(a, u);
  const double two_pi = 2.0 * 3.14159265358979323846;
  RawMesh mesh;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double t = two_pi * i / n;
    const core::Vec3 p = base + (u * std::cos(t) + v * std::sin(t)) * r;
    mesh.points.push_back(p);
    mesh.points.push_back(p + a * length);
  }
  const auto bottom = static_cast<std::uint32_t>(mesh.points.size());
  mesh.points.push_back(base);
  mesh.points.push_back(base + a * length);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({2 * i, 2 * j, 2 * j + 1});
    mesh.triangles.push_back({2 * i, 2 * j + 1, 2 * i + 1});
    mesh.triangles.push_back({bottom, 2 * j, 2 * i});
    mesh.triangles.push_back({bottom + 1, 2 * i + 1, 2 * j + 1});
  }
  return mesh;
}

// A solid of revolution about Z: the profile's (radius, z) points from the bottom up (radii > 0,
// z increasing), N sides, both ends capped. With HOLE_R > 0 it is a tube of that bore (every profile
// radius must exceed it). Outward.
inline RawMesh revolve(const std::vector<std::array<double, 2>>& profile, std::uint32_t n, double hole_r = 0.0) {
  const double two_pi = 2.0 * 3.14159265358979323846;
  RawMesh mesh;
  const auto rings = static_cast<std::uint32_t>(profile.size());
  auto at = [&](std::uint32_t ring, std::uint32_t i) { return ring * n + i % n; };
  for (const auto& [r, z] : profile) {
    for (std::uint32_t i = 0; i < n; ++i) mesh.points.push_back({r * std::cos(two_pi * i / n), r * std::sin(two_pi * i / n), z});
  }
  for (std::uint32_t k = 0; k + 1 < rings; ++k) {
    for (std::uint32_t i = 0; i < n; ++i) {
      mesh.triangles.push_back({at(k, i), at(k, i + 1), at(k + 1, i + 1)});
      mesh.triangles.push_back({at(k, i), at(k + 1, i + 1), at(k + 1, i)});
    }
  }
  const double z0 = profile.front()[1], z1 = profile.back()[1];
  if (hole_r <= 0.0) {
    const auto b = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.push_back({0, 0, z0});
    mesh.points.push_back({0, 0, z1});
    for (std::uint32_t i = 0; i < n; ++i) {
      mesh.triangles.push_back({b, at(0, i + 1), at(0, i)});
      mesh.triangles.push_back({b + 1, at(rings - 1, i), at(rings - 1, i + 1)});
    }
    return mesh;
  }
  const auto h = static_cast<std::uint32_t>(mesh.points.size());  // the bore: ring h (bottom), h + n (top)
  for (double z : {z0, z1}) {
    for (std::uint32_t i = 0; i < n; ++i) mesh.points.push_back({hole_r * std::cos(two_pi * i / n), hole_r * std::sin(two_pi * i / n), z});
  }
  auto bore = [&](std::uint32_t top, std::uint32_t i) { return h + top * n + i % n; };
  for (std::uint32_t i = 0; i < n; ++i) {
    mesh.triangles.push_back({bore(0, i), bore(1, i + 1), bore(0, i + 1)});  // the bore faces the axis
    mesh.triangles.push_back({bore(0, i), bore(1, i), bore(1, i + 1)});
    mesh.triangles.push_back({at(0, i), bore(0, i + 1), at(0, i + 1)});     // bottom annulus, down
    mesh.triangles.push_back({at(0, i), bore(0, i), bore(0, i + 1)});
    mesh.triangles.push_back({at(rings - 1, i), at(rings - 1, i + 1), bore(1, i + 1)});  // top annulus, up
    mesh.triangles.push_back({at(rings - 1, i), bore(1, i + 1), bore(1, i)});
  }
  return mesh;
}

// A leaning tower: circles of radius R whose centres move along +X by tan(LEAN_DEG) per mm of height
// up to LEAN_H, then rise straight to H; N sides, a ring every mm, both ends capped. Its +X side
// overhangs by LEAN_DEG, then stands vertical.
inline RawMesh leaning_tower(double r, double lean_deg, double lean_h, double h, std::uint32_t n) {
  RawMesh m;
  const auto rings = static_cast<std::uint32_t>(std::ceil(h)) + 1;
  const double pi = 3.14159265358979323846, t = std::tan(lean_deg * pi / 180.0);
  for (std::uint32_t k = 0; k < rings; ++k) {
    const double z = std::min(h, static_cast<double>(k)), cx = t * std::min(z, lean_h);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double a = 2.0 * pi * i / n;
      m.points.push_back({cx + r * std::cos(a), r * std::sin(a), z});
    }
  }
  for (std::uint32_t k = 0; k + 1 < rings; ++k) {
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = k * n + i, b = k * n + (i + 1) % n;
      m.triangles.push_back({a, b, b + n});
      m.triangles.push_back({a, b + n, a + n});
    }
  }
  const auto bottom = static_cast<std::uint32_t>(m.points.size());
  const std::uint32_t top = bottom + 1;
  m.points.push_back({0.0, 0.0, 0.0});
  m.points.push_back({t * std::min(h, lean_h), 0.0, h});
  for (std::uint32_t i = 0; i < n; ++i) {
    m.triangles.push_back({bottom, static_cast<std::uint32_t>((i + 1) % n), i});
    m.triangles.push_back({top, (rings - 1) * n + i, (rings - 1) * n + (i + 1) % n});
  }
  return m;
}

// A solid bar whose horizontal section is a square of side W centred on a helix about Z (radius
// R, TURNS turns over height H, starting at (R, 0, 0)): every section the same square, moved along
// the helix (the reference part spiral.scad, solid). A square every STEP_MM of height, ends capped.
inline RawMesh helical_bar(double w, double r, double turns, double h, double step_mm) {
  RawMesh m;
  const double pi = 3.14159265358979323846;
  const auto levels = static_cast<std::uint32_t>(std::ceil(h / step_mm)) + 1;
  const double corner[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
  for (std::uint32_t k = 0; k < levels; ++k) {
    const double z = std::min(h, k * step_mm), a = 2.0 * pi * turns * z / h;
    for (const auto& c : corner) m.points.push_back({r * std::cos(a) + w * c[0], r * std::sin(a) + w * c[1], z});
  }
  for (std::uint32_t k = 0; k + 1 < levels; ++k) {
    for (std::uint32_t i = 0; i < 4; ++i) {
      const std::uint32_t a = 4 * k + i, b = 4 * k + (i + 1) % 4;
      m.triangles.push_back({a, b, b + 4});
      m.triangles.push_back({a, b + 4, a + 4});
    }
  }
  const std::uint32_t t = 4 * (levels - 1);
  m.triangles.push_back({0, 2, 1});
  m.triangles.push_back({0, 3, 2});
  m.triangles.push_back({t, t + 1, t + 2});
  m.triangles.push_back({t, t + 2, t + 3});
  return m;
}

// A bar of L × W turning about Z by TWIST_DEG from z = 0 to H (OpenSCAD's linear_extrude with
// twist), in LEVELS slices: its sections between slices are the quads' diagonals cut flat.
inline RawMesh twisted_bar(double l, double w, double twist_deg, double h, std::uint32_t levels) {
  RawMesh m;
  const double pi = 3.14159265358979323846;
  const double corner[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
  for (std::uint32_t k = 0; k <= levels; ++k) {
    const double z = h * k / levels, a = twist_deg * pi / 180.0 * k / levels;
    for (const auto& c : corner) {
      const double x = l * c[0], y = w * c[1];
      m.points.push_back({x * std::cos(a) - y * std::sin(a), x * std::sin(a) + y * std::cos(a), z});
    }
  }
  for (std::uint32_t k = 0; k < levels; ++k) {
    for (std::uint32_t i = 0; i < 4; ++i) {
      const std::uint32_t a = 4 * k + i, b = 4 * k + (i + 1) % 4;
      m.triangles.push_back({a, b, b + 4});
      m.triangles.push_back({a, b + 4, a + 4});
    }
  }
  const std::uint32_t t = 4 * levels;
  m.triangles.push_back({0, 2, 1});
  m.triangles.push_back({0, 3, 2});
  m.triangles.push_back({t, t + 1, t + 2});
  m.triangles.push_back({t, t + 2, t + 3});
  return m;
}

// A spherical cap on the XY plane: the sphere of radius R cut at height H (0 < H <= R) above its
// centre's side: its base disc at z = 0 and its top at z = H; N segments around, M rings.
inline RawMesh spherical_cap(double r, double h, std::uint32_t n, std::uint32_t m) {
  const double two_pi = 2.0 * 3.14159265358979323846;
  const double zc = h - r;  // the sphere's centre
  const double phi0 = std::acos(std::clamp(-zc / r, -1.0, 1.0));  // polar angle of the base ring
  RawMesh mesh;
  for (std::uint32_t k = 0; k < m; ++k) {  // rings from the base (k = 0) up
    const double phi = phi0 * (1.0 - static_cast<double>(k) / m);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double t = two_pi * i / n;
      mesh.points.push_back({r * std::sin(phi) * std::cos(t), r * std::sin(phi) * std::sin(t), k == 0 ? 0.0 : zc + r * std::cos(phi)});
    }
  }
  const auto top = static_cast<std::uint32_t>(mesh.points.size());
  mesh.points.push_back({0.0, 0.0, h});
  mesh.points.push_back({0.0, 0.0, 0.0});
  auto id = [&](std::uint32_t k, std::uint32_t i) { return k * n + i % n; };
  for (std::uint32_t k = 0; k + 1 < m; ++k) {
    for (std::uint32_t i = 0; i < n; ++i) {
      mesh.triangles.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      mesh.triangles.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    mesh.triangles.push_back({id(m - 1, i), id(m - 1, i + 1), top});
    mesh.triangles.push_back({top + 1, id(0, i + 1), id(0, i)});
  }
  return mesh;
}

// A piece of a thick spherical shell: the solid between the spheres of radii R_IN < R_OUT about
// CENTRE within the polar angle THETA_DEG (< 90) of +Z, its rim a cone through the centre; N
// segments around, M rings from the pole. Each face is turned to face away from the solid.
inline RawMesh shell_patch(core::Vec3 centre, double r_in, double r_out, double theta_deg, std::uint32_t n, std::uint32_t m) {
  const double two_pi = 2.0 * 3.14159265358979323846, theta = theta_deg * 3.14159265358979323846 / 180.0;
  RawMesh mesh;
  auto dir = [&](double phi, double t) { return core::Vec3{std::sin(phi) * std::cos(t), std::sin(phi) * std::sin(t), std::cos(phi)}; };
  // Sphere s (0 inner, 1 outer): the pole, then rings k = 1..m.
  for (const double r : {r_in, r_out}) {
    mesh.points.push_back(centre + core::Vec3{0, 0, r});
    for (std::uint32_t k = 1; k <= m; ++k) {
      for (std::uint32_t i = 0; i < n; ++i) {
        mesh.points.push_back(centre + dir(theta * k / m, two_pi * i / n) * r);
      }
    }
  }
  const std::uint32_t per = 1 + n * m;
  auto id = [&](std::uint32_t s, std::uint32_t k, std::uint32_t i) { return s * per + (k == 0 ? 0 : 1 + (k - 1) * n + i % n); };
  auto at = [&](std::uint32_t v) { return mesh.points[v]; };
  // Adds A B C turned so its normal points along OUT(centroid).
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, auto out) {
    const core::Vec3 pa = at(a), pb = at(b), pc = at(c);
    if (core::dot(core::cross(pb - pa, pc - pa), out((pa + pb + pc) / 3.0)) < 0.0) std::swap(b, c);
    mesh.triangles.push_back({a, b, c});
  };
  for (std::uint32_t s = 0; s < 2; ++s) {
    auto out = [&](core::Vec3 q) { return s == 1 ? q - centre : centre - q; };
    for (std::uint32_t i = 0; i < n; ++i) add(id(s, 0, 0), id(s, 1, i), id(s, 1, i + 1), out);
    for (std::uint32_t k = 1; k < m; ++k) {
      for (std::uint32_t i = 0; i < n; ++i) {
        add(id(s, k, i), id(s, k, i + 1), id(s, k + 1, i + 1), out);
        add(id(s, k, i), id(s, k + 1, i + 1), id(s, k + 1, i), out);
      }
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    auto out = [&](core::Vec3 q) {  // along the polar angle, away from the axis: e_t × e_r
      const core::Vec3 r = core::normalized(q - centre);
      return core::cross(core::cross(core::Vec3{0, 0, 1}, r), r);
    };
    add(id(0, m, i), id(0, m, i + 1), id(1, m, i + 1), out);
    add(id(0, m, i), id(1, m, i + 1), id(1, m, i), out);
  }
  return mesh;
}

// Appends B to A (indices shifted).
inline RawMesh join(RawMesh a, const RawMesh& b) {
  const auto offset = static_cast<std::uint32_t>(a.points.size());
  a.points.insert(a.points.end(), b.points.begin(), b.points.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return a;
}

inline RawMesh flipped(RawMesh a) {
  for (auto& t : a.triangles) std::swap(t[1], t[2]);
  return a;
}

// Every triangle with its own three points (an STL-like soup).
inline RawMesh soup(const RawMesh& a) {
  RawMesh s;
  for (auto t : a.triangles) {
    const auto base = static_cast<std::uint32_t>(s.points.size());
    for (auto v : t) s.points.push_back(a.points[v]);
    s.triangles.push_back({base, base + 1, base + 2});
  }
  return s;
}

// Binary STL bytes of A.
inline std::string binary_stl(const RawMesh& a, const std::string& header = "polyaxis test") {
  std::string out(80, ' ');
  out.replace(0, std::min<std::size_t>(header.size(), 80), header.substr(0, 80));
  auto put_u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  auto put_f32 = [&](double v) {
    const float f = static_cast<float>(v);
    out.append(reinterpret_cast<const char*>(&f), 4);
  };
  put_u32(static_cast<std::uint32_t>(a.triangles.size()));
  for (auto t : a.triangles) {
    for (int i = 0; i < 3; ++i) put_f32(0.0);
    for (auto v : t) {
      put_f32(a.points[v].x);
      put_f32(a.points[v].y);
      put_f32(a.points[v].z);
    }
    out.append(2, '\0');
  }
  return out;
}

// ASCII STL text of A.
inline std::string ascii_stl(const RawMesh& a, const std::string& name = "part") {
  std::string out = "solid " + name + "\n";
  char buf[256];
  for (auto t : a.triangles) {
    out += "  facet normal 0 0 0\n    outer loop\n";
    for (auto v : t) {
      std::snprintf(buf, sizeof buf, "      vertex %.9g %.9g %.9g\n", a.points[v].x, a.points[v].y, a.points[v].z);
      out += buf;
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid " + name + "\n";
  return out;
}

}  // namespace polyaxis::test
