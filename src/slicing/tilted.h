// Tilted "3-D" layers along the centroidal axis (private to the slicing module).
#pragma once

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::slicing::detail {

core::Result<SliceResult> slice_tilted(const mesh::Mesh& mesh, const SliceOptions& options, const mesh::EdgeTopology* topology);

}  // namespace polyaxis::slicing::detail
