// Writing output files so that a failure never leaves a partial file (RELIABILITY O5).
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"

namespace polyaxis::io {

// Writes BYTES to a temporary file beside PATH, fsyncs it and renames it over PATH. On any
// failure the temporary file is removed and PATH is untouched: Error kOutput naming the path.
core::Status write_file_atomic(const std::string& path, std::string_view bytes);

}  // namespace polyaxis::io
