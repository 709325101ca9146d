// Toolpaths of conformal layers (private to the toolpath module).
#pragma once

#include <string>

#include "polyaxis/mesh/distance.h"
#include "polyaxis/slicing/layer.h"
#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::toolpath::detail {

// The paths of conformal LAYER, made on its projection, carried onto its surface: every path is
// cut into pieces no longer than STEP_MM, each point is lifted along the layer's normal onto the
// level set (slicing::lift) and takes the distance's gradient as its tool axis. A travel point the
// surface cannot hold keeps the straight line between its lifted neighbours. The lengths of
// PATHS are recomputed. Returns a message naming the first deposit point that cannot be lifted,
// empty on success.
std::string drape(const mesh::SurfaceDistance& base, const slicing::Layer& layer, double step_mm, LayerToolpaths& paths);

}  // namespace polyaxis::toolpath::detail
