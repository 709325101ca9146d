// The full analysis pipeline of `polyaxis analyze` (repair, centroidal axis, decomposition) and the
// checks every decomposition must pass, shared by the decomposition tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/analysis/decompose.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"
#include "support/repaired.h"

namespace polyaxis::analysis::test {

inline constexpr double kTestPi = 3.14159265358979323846;
// Directions are expected within 5° (parts/README.md); volumes sum to the part within 0.1%.
inline constexpr double kDirectionToleranceDeg = 5.0;
inline constexpr double kVolumeRelTolerance = 1e-3;

inline double angle_between_deg(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)) * 180.0 / kTestPi;
}

// Repair as `polyaxis analyze` does (no self-intersection pass).
using polyaxis::test::repaired;

inline mesh::RepairedMesh reference_part(const std::string& name) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/" + name + ".stl");
  EXPECT_TRUE(read.ok());
  return repaired(std::move(read.value().mesh));
}

// Centroidal axis along +Z, then the decomposition, with the defaults of `polyaxis analyze`.
inline RegionTree pipeline(const mesh::RepairedMesh& part) {
  CentroidalAxisOptions ao;
  ao.start_direction = {0, 0, 1};
  auto axis = centroidal_axis(part.mesh, part.topology, ao);
  EXPECT_TRUE(axis.ok());
  DecomposeOptions dopt;
  auto tree = decompose(part.mesh, axis.value(), dopt);
  EXPECT_TRUE(tree.ok());
  return std::move(tree.value());
}

// A region is one solid: its shells (vertex-connected pieces) may be apart but never touch, as
// the pieces of a cut put back side by side without a union would (they share positions along the
// cap, and the next cut of such a mesh can crash CGAL).
inline void expect_no_touching_shells(const mesh::Mesh& m, std::uint32_t id) {
  std::vector<std::uint32_t> root(m.vertices.size());
  for (std::uint32_t i = 0; i < root.size(); ++i) root[i] = i;
  auto find = [&](std::uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (const auto& t : m.triangles) root[find(t[0])] = find(t[1]), root[find(t[1])] = find(t[2]);
  std::map<std::tuple<double, double, double>, std::uint32_t> shell_at;
  std::size_t shared = 0;
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
    const auto key = std::make_tuple(m.vertices[v].x, m.vertices[v].y, m.vertices[v].z);
    auto [it, inserted] = shell_at.emplace(key, find(v));
    if (!inserted && find(it->second) != find(v)) ++shared;
  }
  EXPECT_EQ(shared, 0u) << "region " << id << ": shells touch at " << shared << " points";
}

// Closed regions, in build order (each after its parent and every region its base lies on; its
// parent among those), volumes summing to the part's.
inline void expect_partition(const RegionTree& tree, const mesh::Mesh& part) {
  const double volume = mesh::signed_volume(part);
  double sum = 0.0;
  for (std::size_t i = 0; i < tree.regions.size(); ++i) {
    const Region& r = tree.regions[i];
    EXPECT_EQ(r.id, i);
    EXPECT_TRUE(mesh::build_topology(r.mesh).closed()) << "region " << r.id;
    EXPECT_GT(r.volume_mm3, 0.0) << "region " << r.id;
    if (i == 0) {
      EXPECT_FALSE(r.parent.has_value());
    } else {
      ASSERT_TRUE(r.parent.has_value());
      EXPECT_LT(*r.parent, r.id);
      EXPECT_NE(std::find(r.rests_on.begin(), r.rests_on.end(), *r.parent), r.rests_on.end()) << "region " << r.id;
    }
    for (std::uint32_t below : r.rests_on) EXPECT_LT(below, r.id) << "region " << r.id;
    expect_no_touching_shells(r.mesh, r.id);
    sum += r.volume_mm3;
  }
  EXPECT_NEAR(sum, volume, kVolumeRelTolerance * volume);
}

// Each expected direction matched by its own region within the tolerance; returns the region ids
// in the order of EXPECTED (or -1 where none matched).
inline std::vector<int> match_directions(const RegionTree& tree, const std::vector<Vec3>& expected) {
  std::vector<int> out;
  std::vector<char> used(tree.regions.size(), 0);
  for (const Vec3& e : expected) {
    int pick = -1;
    double best = kDirectionToleranceDeg;
    for (std::size_t i = 0; i < tree.regions.size(); ++i) {
      const double a = angle_between_deg(tree.regions[i].build_direction, e);
      if (!used[i] && a < best) best = a, pick = static_cast<int>(i);
    }
    EXPECT_GE(pick, 0) << "no region builds along (" << e.x << ", " << e.y << ", " << e.z << ")";
    if (pick >= 0) used[static_cast<std::size_t>(pick)] = 1;
    out.push_back(pick);
  }
  return out;
}

// Each region's base rests on material built before it, checked on the regions' meshes alone:
// points spread over its facets on its base plane, kUnderBaseMm below it, lie inside a region
// before it (winding number). At most kStrayOverhangMm2 of a base may be over nothing: a base over
// a film of its parent (a cut moved off a face of the child's own underside) or over air is not.
// The root (on the plate) and regions built downwards from the plate are left out.
inline constexpr double kUnderBaseMm = 0.01;
inline constexpr double kStrayOverhangMm2 = 0.5;
inline void expect_bases_rest_on_earlier_regions(const RegionTree& tree) {
  constexpr double kSampleMm2 = 0.5;  // about one point per this much base
  constexpr int kMaxSamplesPerFacet = 64;
  std::uint64_t lcg = 12345;
  auto uniform = [&] { return static_cast<double>((lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL) >> 11) / 9007199254740992.0; };
  for (std::size_t i = 1; i < tree.regions.size(); ++i) {
    const Region& r = tree.regions[i];
    if (r.rule == "below the plate") continue;
    const Vec3 bn = core::normalized(r.base_normal);
    double over_nothing = 0.0;
    for (std::size_t f = 0; f < r.mesh.triangles.size(); ++f) {
      const Vec3 a = r.mesh.corner(f, 0), b = r.mesh.corner(f, 1), c = r.mesh.corner(f, 2);
      bool on_base = true;
      for (const Vec3& q : {a, b, c}) on_base = on_base && std::fabs(core::dot(q - r.base_point, bn)) <= 1e-6;
      const double area = core::norm(mesh::face_area_vector(r.mesh, f)) / 2.0;
      if (!on_base || area == 0.0) continue;
      const int n = std::clamp(static_cast<int>(std::ceil(area / kSampleMm2)), 1, kMaxSamplesPerFacet);
      int missed = 0;
      for (int k = 0; k < n; ++k) {
        double u = uniform(), v = uniform();
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        const Vec3 p = a + (b - a) * u + (c - a) * v - bn * kUnderBaseMm;
        double w = 0.0;
        for (std::size_t j = 0; j < i; ++j) w += mesh::winding_number(tree.regions[j].mesh, p);
        missed += w < 0.5 ? 1 : 0;
      }
      over_nothing += area * missed / n;
    }
    EXPECT_LT(over_nothing, kStrayOverhangMm2) << "region " << r.id << ": " << over_nothing << " mm2 of its base over nothing";
  }
}

// Each region support-free in its own direction at the default 30°: its flag, and, counted here
// from its facets, less than kStrayOverhangMm2 of facets facing down past the limit off its base
// plane (the cut's slivers where a plane grazes a tessellated curve).
inline void expect_support_free(const RegionTree& tree) {
  for (const Region& r : tree.regions) {
    EXPECT_TRUE(r.support_free) << "region " << r.id << ": " << r.unsupported_area_mm2 << " mm2, " << r.mid_air_starts.size()
                                << " corners starting in mid-air"
                                << (r.mid_air_starts.empty() ? std::string{}
                                                             : " (" + std::to_string(r.mid_air_starts[0].x) + ", " + std::to_string(r.mid_air_starts[0].y) +
                                                                   ", " + std::to_string(r.mid_air_starts[0].z) + ")");
    const Vec3 d = core::normalized(r.build_direction), bn = core::normalized(r.base_normal);
    double overhang = 0.0;
    for (std::size_t f = 0; f < r.mesh.triangles.size(); ++f) {
      const Vec3 a2 = mesh::face_area_vector(r.mesh, f);
      const double len = core::norm(a2);
      if (len == 0.0 || core::dot(a2, d) >= -0.5 * len) continue;  // sin 30°
      bool on_base = true;
      for (int k = 0; k < 3; ++k) on_base = on_base && std::fabs(core::dot(r.mesh.corner(f, k) - r.base_point, bn)) <= 1e-6;
      if (!on_base) overhang += len / 2.0;
    }
    EXPECT_LT(overhang, kStrayOverhangMm2) << "region " << r.id;
  }
  expect_bases_rest_on_earlier_regions(tree);
}

}  // namespace polyaxis::analysis::test
