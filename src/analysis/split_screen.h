// Cheap evaluation of a candidate plane split of a region, before the exact (CGAL) cut, and the
// choice of a region's build direction. Private to the analysis module (decompose.cpp).
#pragma once

#include <span>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::analysis::detail {

using core::Vec3;

// A region's base may lean from its build direction D by at most 90° − α (α the self-supporting
// angle): beyond that the base itself, seen along D, would face sideways rather than down and
// would not rest on the parent. Ruan's splitting faces are within 10°; an inclined bar (35°) grows
// along its own axis from the flat face it stands on.
inline double max_base_tilt_deg(double alpha_deg) { return 90.0 - alpha_deg; }

// The build directions a machine can reach: within the angle whose cosine is MIN_COS of AXIS (the
// root's direction, which stands upright on the table). The default admits every direction.
struct DirectionCone {
  Vec3 axis{0, 0, 1};
  double min_cos = -2.0;
  bool admits(Vec3 unit) const { return core::dot(unit, axis) >= min_cos - 1e-12; }
  // UNIT itself when admitted, else the admitted direction nearest to it (on the cone's rim).
  Vec3 nearest(Vec3 unit) const;
};

struct FacetSample {
  Vec3 normal;      // unit, outward
  double area_mm2;
};

// The facets of M as samples, leaving out those on the plane (BASE_POINT, BASE_NORMAL).
std::vector<FacetSample> facet_samples(const mesh::Mesh& m, Vec3 base_point, Vec3 base_normal);

// Overhang area of FACETS built along unit D at ALPHA_DEG (no noise threshold), mm².
double overhang_of(std::span<const FacetSample> facets, Vec3 d, double alpha_deg);

// The build direction for a region with surface FACETS (its base left out) grown from a base with
// unit normal BASE_NORMAL: the start direction (STARTS, in order of preference) with the least
// overhang; while some overhang remains, a pattern search over directions within max_base_tilt_deg of
// BASE_NORMAL minimising the overhang depth Σ area·max(0, −sin α' − n·d), α' = α − a small margin
// (so a direction that clears the limit does so with some room). Cost O(F) per probe, ~100 probes.
// FINEST_STEP_DEG ends the search (a coarser end is for screening). Only directions REACH admits
// are taken (the base normal itself is moved onto the cone when outside it).
Vec3 best_direction(std::span<const FacetSample> facets, Vec3 base_normal, std::span<const Vec3> starts, double alpha_deg,
                    double finest_step_deg = 0.25, const DirectionCone& reach = {});

// For each of TARGETS, the facet of M nearest to it. O(F) per target.
std::vector<std::uint32_t> nearest_facets(const mesh::Mesh& m, std::span<const Vec3> targets);

struct Screened {
  bool valid = false;        // the plane splits the region and the child side holds a target
  double parent_mm2 = 0.0;   // the parent's overhang in its own direction, cap included
  double child_mm2 = 0.0;    // the child's overhang along child_direction
  double child_area_mm2 = 0.0;  // the child's surface, cap left out
  Vec3 child_direction;
  double total() const { return parent_mm2 + child_mm2; }
};

// What screen_split needs of every facet of a host, whatever the plane: its unit normal and area,
// whether it lies on the host's base and whether it overhangs along the host's direction; and the
// sums over the host (so a candidate visits only the facets of its child). Cost O(F).
struct HostFaces {
  std::vector<Vec3> normal;
  std::vector<double> area_mm2;  // 0 for a degenerate facet (then no normal)
  std::vector<char> on_base, overhangs;
  double area_sum_mm2 = 0.0, overhang_sum_mm2 = 0.0;  // overhang: off the base only
  double volume_mm3 = 0.0;                             // of the host (divergence theorem)
};
HostFaces host_faces(const mesh::Mesh& m, Vec3 direction, Vec3 base_point, Vec3 base_normal, double alpha_deg);

struct HostRegion {
  const mesh::Mesh* mesh;
  const mesh::EdgeTopology* topology;
  Vec3 direction, base_point, base_normal;
  bool keep_base = false;  // a child that would take facets of the host's base is not valid
  DirectionCone reach;     // the child's build direction stays inside it
  const HostFaces* faces = nullptr;  // host_faces of the above, at the screening's alpha
  double min_thickness_mm = 0.0;     // a cut leaving a piece thinner than this on average is not valid
};

// Estimates the split of HOST by the plane (POINT, unit NORMAL pointing to the child side): the
// child is the surface on the normal side connected to SEEDS (nearest_facets of the branch's
// points; those not on the child side are left out); every other part stays with the parent. Facet areas are clipped exactly at
// the plane; pieces touching only through the cap are not joined (the exact cut does). A split
// whose child or parent would be thinner on average than HOST.min_thickness_mm (twice its volume
// over its surface, both from the clipped facets and the cap) is not valid. Cost: the child's
// facets and their corners (HOST.faces holds the rest).
Screened screen_split(const HostRegion& host, Vec3 point, Vec3 normal, std::span<const std::uint32_t> seeds,
                      std::span<const Vec3> direction_starts, double alpha_deg);

}  // namespace polyaxis::analysis::detail
