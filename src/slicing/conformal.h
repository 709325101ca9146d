// Conformal layers (private to the slicing module; the public part is slicing/conformal.h).
#pragma once

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::slicing::detail {

core::Result<SliceResult> slice_conformal(const mesh::Mesh& mesh, const SliceOptions& options);

}  // namespace polyaxis::slicing::detail
