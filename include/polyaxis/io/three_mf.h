// 3MF reader (lib3mf): every build item's object, with build-item and component transforms
// applied, merged into one mesh.
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/io/read_part.h"

namespace polyaxis::io {

// DATA holds the whole .3mf (zip) archive. Before lib3mf sees it, the zip directory is checked
// against the decompression caps in core/tolerances.h (F15 zip bombs). Errors (kInvalidInput):
// not a zip, no model part, index >= vertex count, component cycle, singular transform, no build
// item. Degenerate triangles are dropped with a warning (an error under options.strict).
core::Result<ReadResult> read_3mf(std::string_view data, const std::string& name, const ReadOptions& options = {});

}  // namespace polyaxis::io
