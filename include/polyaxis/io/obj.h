// Wavefront OBJ reader over bytes in memory: `v` and `f` records; faces with more than three
// corners are triangulated by ear clipping in their own plane; negative (relative) indices are
// resolved; `vt`/`vn` parts of a corner are ignored.
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/io/read_part.h"

namespace polyaxis::io {

// Errors (kInvalidInput) name the line: index 0 or out of range (F14), malformed numbers, NaN/Inf.
core::Result<ReadResult> read_obj(std::string_view data, const std::string& name, const ReadOptions& options = {});

}  // namespace polyaxis::io
