// Reading small text files (machine, process and plan files, G-code) with a size cap.
#pragma once

#include <cstdint>
#include <string>

#include "polyaxis/core/result.h"

namespace polyaxis::io {

// The whole of PATH, a regular file of at most MAX_BYTES. Directories, FIFOs, devices, missing
// or unreadable files and larger files are Error kInvalidInput naming the path.
core::Result<std::string> read_text_file(const std::string& path, std::uint64_t max_bytes);

}  // namespace polyaxis::io
