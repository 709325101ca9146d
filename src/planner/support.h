// The layer-by-layer support check of a plan. Private to the planner module (plan.cpp).
#pragma once

#include <vector>

#include "polyaxis/process/process.h"
#include "polyaxis/planner/plan.h"

namespace polyaxis::planner::detail {

// Fills PLAN.layer_reports (thickness, area, tilt, unsupported area and pieces) from its layers,
// toolpaths and placed regions, adds up plan.unsupported_area_mm2 and clears the support_free of
// each placed region with an unsupported layer.
//
// A layer rests on what lies under it: the region's previous layer, and the material of every
// region built before (sectioned one layer thickness below, along the region's direction). What
// reaches beyond that, grown by t·tan(α) (by more where the torch tilts over it: tilted_step_mm),
// is unsupported. The first layer of the first region stands on the table, as does any
// region's first layer built upright from the table's top. The earlier
// regions are sectioned only for a layer that overhangs its own previous layer (and for every
// region's first layer), so a single-region plan costs nothing more. Cost: O(F) per such layer.
void check_support(Plan& plan, const process::ProcessConfig& process);

// How far (mm) a layer T_MM thick may reach beyond the layer below where the torch is tilted so
// that the self-supporting cone, measured from the torch axis, leans TILTED_DEG (= α + θ) from the
// layer's normal: Kapil et al. (Fig. 4, Eq. 1-3) tilt the torch along an overhanging wall so the
// bead is laid on the wall below; the bead still has to rest on that layer, so the step is at
// most MAX_STEP_MM (process max_step_bead_share · bead width) however far the torch leans, and
// never less than the untilted t·tan(ALPHA_DEG). Bounded for every setting.
double tilted_step_mm(double t_mm, double tilted_deg, double alpha_deg, double max_step_mm);

}  // namespace polyaxis::planner::detail
