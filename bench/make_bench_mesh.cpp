// Writes a closed, watertight, bunny-like binary STL test mesh for the slicing benchmark.
// Usage: make_bench_mesh LEVEL OUT.stl   (LEVEL 0..10; 20·4^LEVEL triangles:
//        6 → 81 920, 7 → 327 680, 8 → 1 310 720, 9 → 5 242 880)
//
// How it is made: a regular icosahedron is subdivided LEVEL times (each triangle split into four
// by its edge midpoints, shared midpoints created once, every new vertex pushed back onto the unit
// sphere), which gives a geodesic sphere with 10·4^LEVEL + 2 vertices. Each vertex is then moved
// along its own direction d to radius r(d) = 50 mm · (1 + bump(d)), where bump is a smooth sum
// of a few sinusoids of different frequencies plus two Gaussian lobes ("ears" and a "tail"), so
// that sections are non-trivial: several loops' worth of varying curvature, concave and convex
// stretches, and lobes that appear and disappear from layer to layer. Since r > 0 everywhere, the
// surface is a radial graph over the sphere: each triangle lies in the cone from the centre over
// its spherical triangle, so the mesh is closed, 2-manifold, consistently oriented (outward) and
// free of self-intersections by construction. Finally the mesh is scaled uniformly so that it is
// exactly 100 mm tall (500 layers of 0.2 mm) and moved so that it stands on z = 0, centred at
// x = y = 100 mm (the middle of a 200 × 200 mm bed). Vertices are shared by index and written
// from the same float values, so the STL is watertight bit for bit.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <unordered_map>
#include <vector>

namespace {

using Vec = std::array<double, 3>;
using Tri = std::array<std::uint32_t, 3>;

Vec normalized(Vec v) {
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / len, v[1] / len, v[2] / len};
}

double gaussian_lobe(const Vec& d, const Vec& centre, double sharpness) {
  const Vec c = normalized(centre);
  const double dx = d[0] - c[0], dy = d[1] - c[1], dz = d[2] - c[2];
  return std::exp(-sharpness * (dx * dx + dy * dy + dz * dz));
}

// Smooth relative displacement of the unit direction d; stays within about [-0.3, 0.45].
double bump(const Vec& d) {
  const double x = d[0], y = d[1], z = d[2];
  return 0.10 * std::sin(2.0 * x + 1.3 * y + 0.5) * std::cos(1.7 * z - 0.4)   // broad body shape
         + 0.06 * std::sin(5.1 * x - 3.3 * z + 1.0) * std::sin(4.2 * y + 0.7)  // medium bumps
         + 0.03 * std::cos(9.0 * y + 7.0 * z)                                  // ripples
         + 0.012 * std::sin(17.0 * x + 11.0 * y - 13.0 * z)                    // fine ripples
         + 0.30 * gaussian_lobe(d, {0.35, 0.25, 0.90}, 14.0)                   // "ear"
         + 0.25 * gaussian_lobe(d, {-0.30, 0.35, 0.88}, 16.0)                  // "ear"
         + 0.12 * gaussian_lobe(d, {-0.95, -0.10, -0.20}, 10.0)                // "tail"
         - 0.08 * gaussian_lobe(d, {0.60, -0.70, 0.10}, 6.0);                  // a dent
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_bench_mesh LEVEL OUT.stl   (20*4^LEVEL triangles, LEVEL 0..10)\n");
    return 2;
  }
  const int level = std::atoi(argv[1]);
  if (level < 0 || level > 10) {
    std::fprintf(stderr, "make_bench_mesh: LEVEL must be in 0..10\n");
    return 2;
  }

  // Regular icosahedron, faces counter-clockwise seen from outside.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec> vertices;
  for (const Vec& v : std::vector<Vec>{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                       {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                       {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}}) {
    vertices.push_back(normalized(v));
  }
  std::vector<Tri> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};

  for (int k = 0; k < level; ++k) {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    midpoints.reserve(faces.size() * 3 / 2 + 16);
    vertices.reserve(vertices.size() + faces.size() * 3 / 2);
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<std::uint32_t>(vertices.size()));
      if (inserted) {
        const Vec& p = vertices[a];
        const Vec& q = vertices[b];
        vertices.push_back(normalized({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
      }
      return it->second;
    };
    std::vector<Tri> next;
    next.reserve(faces.size() * 4);
    for (const Tri& f : faces) {
      const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    faces.swap(next);
  }

  // Displace radially, then scale to 100 mm tall, stand on z = 0, centre at x = y = 100.
  for (Vec& v : vertices) {
    const double r = 50.0 * (1.0 + bump(v));
    v = {r * v[0], r * v[1], r * v[2]};
  }
  Vec lo = vertices.front(), hi = vertices.front();
  for (const Vec& v : vertices) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], v[i]);
      hi[i] = std::max(hi[i], v[i]);
    }
  }
  const double scale = 100.0 / (hi[2] - lo[2]);
  std::vector<std::array<float, 3>> points(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec& v = vertices[i];
    points[i] = {static_cast<float>(100.0 + scale * (v[0] - 0.5 * (lo[0] + hi[0]))),
                 static_cast<float>(100.0 + scale * (v[1] - 0.5 * (lo[1] + hi[1]))),
                 static_cast<float>(scale * (v[2] - lo[2]))};
  }

  std::FILE* f = std::fopen(argv[2], "wb");
  if (!f) {
    std::perror(argv[2]);
    return 6;
  }
  char header[80] = "polyaxis benchmark mesh: bumpy geodesic sphere, 100 mm tall";
  std::fwrite(header, 1, 80, f);
  const auto count = static_cast<std::uint32_t>(faces.size());
  std::fwrite(&count, 4, 1, f);
  std::vector<unsigned char> record(50 * 4096);
  std::size_t used = 0;
  for (const Tri& tri : faces) {
    const auto& a = points[tri[0]];
    const auto& b = points[tri[1]];
    const auto& c = points[tri[2]];
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double wx = c[0] - a[0], wy = c[1] - a[1], wz = c[2] - a[2];
    const Vec n = normalized({uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx});
    const float normal[3] = {static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])};
    unsigned char* out = record.data() + used;
    std::copy_n(reinterpret_cast<const unsigned char*>(normal), 12, out);
    std::copy_n(reinterpret_cast<const unsigned char*>(a.data()), 12, out + 12);
    std::copy_n(reinterpret_cast<const unsigned char*>(b.data()), 12, out + 24);
    std::copy_n(reinterpret_cast<const unsigned char*>(c.data()), 12, out + 36);
    out[48] = 0;
    out[49] = 0;
    used += 50;
    if (used == record.size()) {
      std::fwrite(record.data(), 1, used, f);
      used = 0;
    }
  }
  std::fwrite(record.data(), 1, used, f);
  if (std::fclose(f) != 0) {
    std::perror(argv[2]);
    return 6;
  }
  std::printf("%u triangles, %zu vertices, %.1f x %.1f x 100.0 mm\n", count, vertices.size(),
              scale * (hi[0] - lo[0]), scale * (hi[1] - lo[1]));
  return 0;
}
