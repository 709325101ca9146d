// How closely a plan's layers reproduce the part (SPEC §3, "fidelity"). Private to the planner.
#pragma once

#include "polyaxis/planner/plan.h"

namespace polyaxis::planner::detail {

// Sets PLAN.fidelity from its layers and placed regions:
// - max_cusp_mm: the largest staircase height t·|n·d| over the layers, t the layer's largest
//   thickness and n the unit normal of a facet of its region crossing the layer's slab (facets
//   within 1° of flat make no staircase and are left out, as the adaptive slicer does);
// - volume_difference_mm3 and its share of PART_VOLUME_MM3: the volume of the symmetric difference
//   between the deposited layers (each layer's section swept along its normal over its thickness)
//   and the part, each half of a layer's slab taken at its middle (the midpoint rule): the area of
//   the region's section there XOR the layer's section, times the half's thickness. Tilted layers
//   are swept along their own normal by half the thickness on the axis each way (their wedge is
//   not modelled). Conformal layers are swept along the distance's gradient: the region is refined
//   to CONFORMAL_EDGE_MM as the slicer does, and its level sets at the middle of each half of the
//   band are compared with the layer's section, both projected along d (the projected area times
//   the thickness: a steep layer's volume is counted by its projection); their staircase is
//   t·|n·g|, g the gradient at the facet, at most the facet's own span of levels (a facet all but
//   parallel to the levels, such as the faceting of a surface the levels follow, makes no step).
// Layers run in parallel; cost O(F) a layer (two sections of the region).
void measure_fidelity(Plan& plan, double part_volume_mm3, double conformal_edge_mm);

}  // namespace polyaxis::planner::detail
