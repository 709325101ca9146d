// Writes a binary STL torus (major radius 40 mm, minor 15 mm) with about N triangles:
// an n×m grid of quads on the torus, n = 2m, each split in two. Usage: make_torus_stl N OUT.stl
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <array>
#include <algorithm>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_torus_stl TRIANGLES OUT.stl\n");
    return 2;
  }
  const double target = std::atof(argv[1]);
  const auto m = static_cast<std::uint32_t>(std::max(3.0, std::round(std::sqrt(target / 4.0))));
  const std::uint32_t n = 2 * m;
  const double major = 40.0, minor = 15.0, two_pi = 2.0 * 3.14159265358979323846;
  auto point = [&](std::uint32_t i, std::uint32_t j) {
    const double u = two_pi * (i % n) / n, v = two_pi * (j % m) / m;
    return std::array<float, 3>{static_cast<float>((major + minor * std::cos(v)) * std::cos(u)),
                                static_cast<float>((major + minor * std::cos(v)) * std::sin(u)),
                                static_cast<float>(minor * std::sin(v) + minor)};
  };
  std::FILE* f = std::fopen(argv[2], "wb");
  if (!f) return 6;
  char header[80] = "polyaxis benchmark torus";
  std::fwrite(header, 1, 80, f);
  const std::uint32_t count = 2 * n * m;
  std::fwrite(&count, 4, 1, f);
  auto facet = [&](std::array<float, 3> a, std::array<float, 3> b, std::array<float, 3> c) {
    const float zero[3] = {0, 0, 0};
    std::fwrite(zero, 4, 3, f);
    std::fwrite(a.data(), 4, 3, f);
    std::fwrite(b.data(), 4, 3, f);
    std::fwrite(c.data(), 4, 3, f);
    const std::uint16_t attr = 0;
    std::fwrite(&attr, 2, 1, f);
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < m; ++j) {
      facet(point(i, j), point(i + 1, j), point(i + 1, j + 1));
      facet(point(i, j), point(i + 1, j + 1), point(i, j + 1));
    }
  }
  std::fclose(f);
  std::printf("%u triangles\n", count);
  return 0;
}
