// The layer-by-layer support check of a plan. Private to the planner module (plan.cpp).
#pragma once

#include <vector>

#include "polyaxis/motion/process.h"
#include "polyaxis/planner/plan.h"

namespace polyaxis::planner::detail {

// Fills PLAN.layer_reports (thickness, area, tilt, unsupported area and pieces) from its layers,
// toolpaths and placed regions, adds up plan.unsupported_area_mm2 and clears the support_free of
// each placed region with an unsupported layer.
//
// A layer rests on what lies under it: the region's previous layer, and the material of every
// region built before (sectioned one layer thickness below, along the region's direction). What
// reaches beyond that, grown by t·tan(α) (by more where the torch tilts over it: PlanOptions in
// plan.h), is unsupported. The first layer of the first region stands on the table, as does any
// region's first layer built upright from the table's top. The earlier
// regions are sectioned only for a layer that overhangs its own previous layer (and for every
// region's first layer), so a single-region plan costs nothing more. Cost: O(F) per such layer.
void check_support(Plan& plan, const motion::ProcessConfig& process);

}  // namespace polyaxis::planner::detail
