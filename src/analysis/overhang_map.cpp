// Overhang map: the facet rule of mesh::overhang_area (SPEC §2.2, α_max after Kapil), then a
// flood fill over shared edges to find connected overhang patches.
#include "polyaxis/analysis/overhang_map.h"

#include <algorithm>
#include <cmath>

#include "polyaxis/core/check.h"
#include "polyaxis/mesh/properties.h"

namespace polyaxis::analysis {

OverhangMap overhang_map(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology, Vec3 build_direction,
                         double self_supporting_rad) {
  POLYAXIS_CHECK(topology.opposite.size() == 3 * mesh.face_count(), "topology does not belong to the mesh");
  POLYAXIS_CHECK(core::is_finite(build_direction) && norm(build_direction) > 0.0, "build direction must be non-zero");
  const Vec3 d = normalized(build_direction);

  OverhangMap map;
  map.build_direction = d;
  map.self_supporting_rad = self_supporting_rad;

  double lowest = INFINITY;
  for (const Vec3& v : mesh.vertices) lowest = std::fmin(lowest, dot(v, d));
  const double limit = -std::sin(self_supporting_rad);

  // Same arithmetic as mesh::overhang_area so the totals agree to the last bit of each facet.
  const std::size_t n = mesh.face_count();
  std::vector<std::uint8_t> over(n, 0);
  for (std::size_t f = 0; f < n; ++f) {
    const Vec3 n2 = mesh::face_area_vector(mesh, f);
    const double len = norm(n2);
    if (len == 0.0 || dot(n2, d) >= limit * len) continue;
    bool on_plate = true;
    for (int k = 0; k < 3; ++k) on_plate = on_plate && dot(mesh.corner(f, k), d) - lowest <= mesh::kPlateContactMm;
    if (on_plate) continue;
    over[f] = 1;
    map.facets.push_back(static_cast<std::uint32_t>(f));
    map.area_mm2 += len / 2.0;
  }

  std::vector<std::uint8_t> seen(n, 0);
  std::vector<std::uint32_t> stack;
  for (const std::uint32_t seed : map.facets) {
    if (seen[seed]) continue;
    OverhangPatch patch;
    patch.lowest_mm = INFINITY;
    patch.highest_mm = -INFINITY;
    Vec3 weighted_centroid{};
    Vec3 normal_sum{};
    seen[seed] = 1;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      patch.facets.push_back(f);
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t h = topology.opposite[3 * f + k];
        if (h == mesh::kNoHalfEdge) continue;
        const std::uint32_t g = h / 3;
        if (over[g] && !seen[g]) {
          seen[g] = 1;
          stack.push_back(g);
        }
      }
    }
    std::sort(patch.facets.begin(), patch.facets.end());
    // Sums in ascending facet order: the same bytes however the fill visited them.
    for (const std::uint32_t f : patch.facets) {
      const Vec3 n2 = mesh::face_area_vector(mesh, f);
      const double area = norm(n2) / 2.0;
      const Vec3 a = mesh.corner(f, 0), b = mesh.corner(f, 1), c = mesh.corner(f, 2);
      patch.area_mm2 += area;
      weighted_centroid = weighted_centroid + (a + b + c) * (area / 3.0);
      normal_sum = normal_sum + normalized(n2) * area;
      for (const Vec3 p : {a, b, c}) {
        patch.lowest_mm = std::fmin(patch.lowest_mm, dot(p, d));
        patch.highest_mm = std::fmax(patch.highest_mm, dot(p, d));
      }
    }
    patch.centroid = weighted_centroid / patch.area_mm2;
    patch.mean_normal = normalized(normal_sum);
    map.patches.push_back(std::move(patch));
  }
  return map;
}

}  // namespace polyaxis::analysis
