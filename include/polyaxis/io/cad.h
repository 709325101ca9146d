// STEP and IGES through OpenCASCADE, tessellated to a chordal tolerance.
#pragma once

#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/io/read_part.h"

namespace polyaxis::io {

// Imports PATH (FORMAT kStep or kIges) in a child process limited to options.import_timeout_s and
// options.import_memory_bytes, because OpenCASCADE can crash or hang on malformed files (F16): a
// crash, a hang or a failed import is an Error (kInvalidInput) "STEP import failed/crashed ...".
// Faces are meshed with BRepMesh to options.chordal_mm and options.angular_deg.
core::Result<ReadResult> read_cad(const std::string& path, Format format, const ReadOptions& options = {});

}  // namespace polyaxis::io
