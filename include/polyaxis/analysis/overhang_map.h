// Overhang map (SPEC §2.2): the facets that overhang for a build direction and self-supporting
// angle, grouped into connected patches (Kapil; Dwivedi & Kovacevic §3, Step 2: "determine the
// overhanging regions of the solid in a given orientation").
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::analysis {

using core::Vec3;

// One connected overhang patch: overhanging facets joined through shared manifold edges.
struct OverhangPatch {
  std::vector<std::uint32_t> facets;  // face ids, ascending
  double area_mm2 = 0.0;
  Vec3 centroid;                      // area-weighted centroid of the facets, mm
  Vec3 mean_normal;                   // unit, area-weighted mean of the facets' unit normals
  double lowest_mm = 0.0;             // min over the patch's corners of p·d (d the unit build direction)
  double highest_mm = 0.0;            // max of p·d
};

struct OverhangMap {
  Vec3 build_direction;               // unit d the map was computed for
  double self_supporting_rad = 0.0;   // α_max from vertical
  std::vector<std::uint32_t> facets;  // every overhanging face id, ascending
  double area_mm2 = 0.0;              // total; equals mesh::overhang_area for the same d and α_max
  // Ordered by their smallest facet id (the order they are found in), so the output is the same
  // for the same mesh.
  std::vector<OverhangPatch> patches;
};

// A facet overhangs when its unit normal n has n·d < −sin(α_max) and not every corner lies within
// mesh::kPlateContactMm of the lowest point along d (it rests on the plate): exactly the rule of
// mesh::overhang_area. Zero-area facets never overhang. Patches join overhanging facets through
// TOPOLOGY.opposite (edges with exactly two faces); facets touching only at a vertex are separate
// patches.
// Preconditions: TOPOLOGY = mesh::build_topology(MESH); BUILD_DIRECTION finite and non-zero (it is
// normalised). Broken preconditions throw core::InvariantError. Cost O(faces), deterministic.
OverhangMap overhang_map(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology, Vec3 build_direction,
                         double self_supporting_rad);

}  // namespace polyaxis::analysis
