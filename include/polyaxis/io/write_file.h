// Writing output files so that a failure never leaves a partial file (RELIABILITY O5).
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"

namespace polyaxis::io {

enum class Durability {
  kSynced,  // fsync before the rename: the file survives a power cut (machine code)
  kAtomic,  // rename only: readers and failures never see a partial file (reports, layers)
};

// Writes BYTES to a temporary file beside PATH and renames it over PATH (after an fsync when
// kSynced). On any failure the temporary file is removed and PATH is untouched: Error kOutput
// naming the path. An existing PATH that is not a regular file (a FIFO, a device, a directory)
// is refused, not replaced.
core::Status write_file_atomic(const std::string& path, std::string_view bytes, Durability durability = Durability::kSynced);

}  // namespace polyaxis::io
