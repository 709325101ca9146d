// Where the root region stands, as the CLI's --root-base and the Python binding's root_base say it.
#pragma once

#include <string>

#include "polyaxis/analysis/decompose.h"
#include "polyaxis/core/result.h"

namespace polyaxis::analysis {

// TEXT as a RootBase: "" (found from the centroidal axis), "z-min" (the lowest point), a planar
// face id, or a plane "px,py,pz,nx,ny,nz" (a point and the root's build direction). kUsage naming
// --root-base otherwise.
core::Result<RootBase> parse_root_base(const std::string& text);

}  // namespace polyaxis::analysis
