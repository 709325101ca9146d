// The build order of the layers of a region tree (SPEC §2.6; Dwivedi §3 Eq. 2–3 and Rules 2–4;
// Ruan §4.2.3). Private to the planner.
//
// C-space contours: each layer's polygons grown by the head's radius (Dwivedi Eq. 3, a polygon
// offset) in the layer's plane. Two layers of different regions, neither region an ancestor of the
// other, interfere when their grown contours overlap in space: along the line where their planes
// meet, or on one plane when the planes are parallel and the layers' slabs overlap.
//
// Interference levels (Rule 2): the regions are walked in build order and each region's layers
// in layer order; a layer that interferes with another gets the lowest level, above its region's
// previous level, that a layer it interferes with already has, else the next level; a layer that
// interferes with nothing keeps level 0.
//
// Order: a child region starts once its father and the regions its base rests on are complete; a
// region goes on with its next layer while that layer has level 0 (Rule 4, no reorientation);
// otherwise the next layer is the one of the lowest-numbered region whose next layer is at the
// lowest level still pending (Rule 3), then any region's at level 0, so interfering brothers are
// built level by level: L1R1, L1R2 … L2R1 …
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/planner/plan.h"

namespace polyaxis::planner::detail {

// The layers (index into LAYERS, which holds every region's layers, regions contiguous and in
// REGIONS' order) in build order, with each layer's LayerOrder (indexed like LAYERS). HEAD_RADIUS_MM
// grows the contours. Without INTERLEAVE each region is built to its end before the next.
struct Sequence {
  std::vector<std::uint32_t> order;   // build position -> index into the layers given
  std::vector<LayerOrder> records;    // indexed like the layers given; interferes_with holds indices into them
};

Sequence sequence_layers(const std::vector<slicing::Layer>& layers, const std::vector<std::uint32_t>& region_of_layer,
                         const std::vector<PlanRegion>& regions, double head_radius_mm, bool interleave);

}  // namespace polyaxis::planner::detail
