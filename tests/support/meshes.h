// Test meshes made in code, served by kind so a property can be checked on all of them.
#pragma once

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
