#include "patch_split.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <tbb/parallel_for.h>

namespace polyaxis::analysis::detail {
namespace {

// Directions tried for a patch's child (a Fibonacci sphere), at most.
constexpr int kPatchDirections = 256;
// A direction qualifies when every facet of the patch is this far inside the self-supporting
// limit along it, degrees.
constexpr double kPatchMarginDeg = 2.0;
// Plane offsets below the patch's lowest point along the normal: this much, mm, then the step
// times each factor.
constexpr double kPatchClearMm = 0.01;
constexpr double kPatchStepFactors[] = {0.5, 2.0};
// Facet visits allowed for screening one patch's candidates (each visits the host's facets once).

constexpr std::size_t kMinPatchCandidates = 24;
constexpr std::size_t kMaxPatchCandidates = 120;
constexpr std::size_t kMaxTargets = 8;

Vec3 fibonacci(int i, int n) {
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  const double z = 1.0 - (2.0 * i + 1.0) / n;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(golden * i), r * std::sin(golden * i), z};
}

}  // namespace

std::vector<PatchCandidate> patch_candidates(const HostRegion& host, const OverhangPatch& patch, double step_mm, double alpha_deg) {
  const mesh::Mesh& m = *host.mesh;
  std::vector<Vec3> normals;
  normals.reserve(patch.facets.size());
  for (std::uint32_t f : patch.facets) normals.push_back(core::normalized(mesh::face_area_vector(m, f)));
  const double limit = -std::sin((alpha_deg - kPatchMarginDeg) * kPi / 180.0);
  std::vector<Vec3> dirs;
  for (int i = 0; i < kPatchDirections; ++i) {
    const Vec3 d = fibonacci(i, kPatchDirections);
    if (std::all_of(normals.begin(), normals.end(), [&](Vec3 n) { return core::dot(n, d) >= limit; })) dirs.push_back(d);
  }
  const std::size_t offsets = 1 + std::size(kPatchStepFactors);
  const double facets = static_cast<double>(std::max<std::size_t>(m.triangles.size(), 1));
  const auto budget = std::clamp(static_cast<std::size_t>(kPatchScreenBudget / facets), kMinPatchCandidates, kMaxPatchCandidates);
  if (dirs.size() * offsets > budget) {
    const std::size_t keep = std::max<std::size_t>(1, budget / offsets);
    std::vector<Vec3> thinned;
    for (std::size_t k = 0; k < keep; ++k) thinned.push_back(dirs[k * dirs.size() / keep]);
    dirs = std::move(thinned);
  }
  std::vector<PatchCandidate> out;
  for (const Vec3& d : dirs) {
    double lo = INFINITY;
    for (std::uint32_t f : patch.facets) {
      for (int k = 0; k < 3; ++k) lo = std::min(lo, core::dot(m.corner(f, k), d));
    }
    out.push_back({d * (lo - kPatchClearMm), d, {}});
    for (double factor : kPatchStepFactors) out.push_back({d * (lo - factor * step_mm), d, {}});
  }
  tbb::parallel_for(std::size_t{0}, out.size(), [&](std::size_t k) {
    PatchCandidate& c = out[k];
    const Vec3 starts[] = {c.normal};
    c.screened = screen_split(host, c.point, c.normal, patch.facets, starts, alpha_deg);
  });
  // The child must stand on its own: a split that only moves overhang into a new region is no cure.
  std::erase_if(out, [](const PatchCandidate& c) { return !c.screened.valid || c.screened.child_mm2 > 0.0; });
  // Best first, on keys rounded to the noise floor so that the order is a strict weak one: overhang
  // left, then the child's surface, then the child's direction nearest the host's.
  const Vec3 hd = core::normalized(host.direction);
  auto key = [&](const PatchCandidate& c) {
    return std::make_tuple(std::llround(c.screened.total() / kUnsupportedNoiseMm2), std::llround(c.screened.child_area_mm2 / kUnsupportedNoiseMm2),
                           -core::dot(c.screened.child_direction, hd));
  };
  std::stable_sort(out.begin(), out.end(), [&](const PatchCandidate& a, const PatchCandidate& b) { return key(a) < key(b); });
  return out;
}

std::vector<Vec3> patch_targets(const mesh::Mesh& m, const OverhangPatch& patch) {
  std::vector<std::pair<double, std::uint32_t>> by_area;
  for (std::uint32_t f : patch.facets) by_area.emplace_back(-core::norm(mesh::face_area_vector(m, f)), f);
  std::stable_sort(by_area.begin(), by_area.end());
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < by_area.size() && i < kMaxTargets; ++i) {
    const std::uint32_t f = by_area[i].second;
    out.push_back((m.corner(f, 0) + m.corner(f, 1) + m.corner(f, 2)) / 3.0);
  }
  return out;
}

}  // namespace polyaxis::analysis::detail
