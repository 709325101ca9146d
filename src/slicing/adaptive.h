// Adaptive planar slicing (private to the slicing module).
#pragma once

#include "polyaxis/core/result.h"
#include "polyaxis/slicing/section.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::slicing::detail {

core::Result<SliceResult> slice_adaptive(const SectionContext& context, const SliceOptions& options);

}  // namespace polyaxis::slicing::detail
