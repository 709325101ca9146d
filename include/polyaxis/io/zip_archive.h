// Zip archives (OPC packages: 3MF parts, the 3MF toolpath), read with the decompression caps of
// core/tolerances.h (RELIABILITY F15: zip bombs) and written deterministically.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "polyaxis/core/result.h"

namespace polyaxis::io {

struct ZipEntry {
  std::uint64_t index = 0;  // in the archive's directory
  std::string path;         // as the directory names it, e.g. "3D/3dmodel.model"
  std::string bytes;        // uncompressed
};

// More entries than any OPC producer writes in one package.
inline constexpr std::uint64_t kMaxZipEntries = 100'000;

// The entries of the archive in DATA whose path WANT accepts, uncompressed, in directory order.
// Before anything is inflated the directory is checked: at most kMaxZipEntries entries, at most
// core::kMax3mfUncompressedBytes in all, and no entry (above 4 MiB) nor the whole expanding beyond
// core::kMax3mfCompressionRatio. Errors (kInvalidInput) start with NAME and call the file KIND
// ("a 3MF file") where it is not a zip archive at all.
core::Result<std::vector<ZipEntry>> read_zip(std::string_view data, const std::string& name, std::string_view kind,
                                             const std::function<bool(std::string_view path)>& want);

// An archive holding ENTRIES (path, bytes) in that order, deflated, with every time stamp at
// 1980-01-01 so that the same entries give the same bytes. kInternal when libzip fails.
core::Result<std::string> write_zip(std::span<const std::pair<std::string, std::string>> entries);

// The archive DATA with each of ENTRIES' paths holding its bytes instead (deflated, stamped at
// 1980-01-01); the other entries are copied as they are, without inflating them. kInternal when a
// path is not in the archive or libzip fails.
core::Result<std::string> replace_zip_entries(std::string_view data, std::span<const std::pair<std::string, std::string>> entries);
core::Result<std::string> replace_zip_entry(std::string_view data, const std::string& path, std::string_view bytes);

}  // namespace polyaxis::io
