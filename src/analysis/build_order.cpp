#include "build_order.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "polyaxis/mesh/properties.h"
#include "region_geometry.h"

namespace polyaxis::analysis::detail {
namespace {

// Probes per region, and how far below the base cap they lie, mm (well above the cut's own noise,
// well below any wall the part could have).
constexpr std::size_t kMaxProbes = 16;
constexpr double kProbeDepthMm = 0.01;

bool in_box(const core::Box3& b, Vec3 p) {
  return p.x >= b.min.x && p.y >= b.min.y && p.z >= b.min.z && p.x <= b.max.x && p.y <= b.max.y && p.z <= b.max.z;
}

// Points just below R's base cap: centroids of its largest facets on the base plane.
std::vector<Vec3> base_probes(const Region& r) {
  const Vec3 bn = core::normalized(r.base_normal);
  std::vector<std::pair<double, std::uint32_t>> cap;
  for (std::uint32_t f = 0; f < r.mesh.triangles.size(); ++f) {
    bool on = true;
    for (int k = 0; k < 3; ++k) on = on && std::fabs(core::dot(r.mesh.corner(f, k) - r.base_point, bn)) <= kOnBaseMm;
    if (on) cap.emplace_back(-core::norm(mesh::face_area_vector(r.mesh, f)), f);
  }
  std::stable_sort(cap.begin(), cap.end());
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < cap.size() && i < kMaxProbes; ++i) {
    const std::uint32_t f = cap[i].second;
    out.push_back((r.mesh.corner(f, 0) + r.mesh.corner(f, 1) + r.mesh.corner(f, 2)) / 3.0 - bn * kProbeDepthMm);
  }
  return out;
}

}  // namespace

void order_by_support(std::vector<Region>& regions) {
  const std::size_t n = regions.size();
  std::vector<std::vector<std::uint32_t>> below(n);  // by index
  std::vector<core::Box3> boxes;
  for (const Region& r : regions) boxes.push_back(mesh::bounding_box(r.mesh));
  for (std::size_t b = 1; b < n; ++b) {
    if (regions[b].parent) below[b].push_back(*regions[b].parent);
    const std::vector<Vec3> probes = base_probes(regions[b]);
    for (std::size_t a = 0; a < n; ++a) {
      if (a == b || std::find(below[b].begin(), below[b].end(), a) != below[b].end()) continue;
      const bool holds = std::any_of(probes.begin(), probes.end(),
                                     [&](Vec3 p) { return in_box(boxes[a], p) && winding(regions[a].mesh, p) > 0.5; });
      if (holds) below[b].push_back(static_cast<std::uint32_t>(a));
    }
  }
  // Region ids are their indices on entry (decompose numbers them so).
  std::vector<std::size_t> order;
  std::vector<char> placed(n, 0);
  while (order.size() < n) {
    std::size_t next = n;
    for (std::size_t i = 0; i < n && next == n; ++i) {
      if (!placed[i] && std::all_of(below[i].begin(), below[i].end(), [&](std::uint32_t a) { return placed[a] != 0; })) next = i;
    }
    if (next == n) {
      // A cycle (not expected: a base lies on material already there). The lowest unplaced region
      // has its parent placed (parents come first on entry); it goes next, and what it would
      // wait for is dropped from its rests_on, so the order still holds for what is listed.
      for (std::size_t i = 0; i < n && next == n; ++i) {
        if (!placed[i]) next = i;
      }
      std::erase_if(below[next], [&](std::uint32_t a) { return placed[a] == 0; });
    }
    placed[next] = 1;
    order.push_back(next);
  }
  std::vector<std::uint32_t> id_of(n);
  for (std::size_t k = 0; k < n; ++k) id_of[order[k]] = static_cast<std::uint32_t>(k);
  std::vector<Region> out;
  out.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    Region r = std::move(regions[order[k]]);
    r.id = static_cast<std::uint32_t>(k);
    if (r.parent) r.parent = id_of[*r.parent];
    r.rests_on.clear();
    for (std::uint32_t a : below[order[k]]) r.rests_on.push_back(id_of[a]);
    std::sort(r.rests_on.begin(), r.rests_on.end());
    out.push_back(std::move(r));
  }
  regions = std::move(out);
}

}  // namespace polyaxis::analysis::detail
