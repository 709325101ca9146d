// STL readers (binary and ASCII) over bytes in memory. Binary is told from ASCII by the size
// invariant 84 + 50·n, never by the word "solid" (F4): 14% of real binary files start with it.
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/io/read_part.h"

namespace polyaxis::io {

// Parses an STL file held in DATA. NAME is used in messages only. Errors (kInvalidInput) name the
// byte offset or line and the facet: truncated binary (F1), no geometry (F3), ASCII cut mid-facet
// (F5), NaN/Inf vertex (F6), too many triangles (F10), compressed data (F11). Warnings: header
// count differs from the size (F2), NaN normals (F6). Linear in the size of DATA.
core::Result<ReadResult> read_stl(std::string_view data, const std::string& name, const ReadOptions& options = {});

}  // namespace polyaxis::io
