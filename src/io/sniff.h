// Recognising file content by its first bytes.
#pragma once

#include <optional>
#include <string_view>

namespace polyaxis::io {

// "gzip" or "zip" when DATA starts with that format's magic number, else nothing (F11).
inline std::optional<std::string_view> compression_of(std::string_view data) {
  if (data.starts_with("\x1f\x8b")) return "gzip";
  if (data.starts_with("PK\x03\x04") || data.starts_with("PK\x05\x06")) return "zip";
  if (data.starts_with("BZh")) return "bzip2";
  if (data.starts_with("\xFD" "7zXZ")) return "xz";
  if (data.starts_with("\x28\xB5\x2F\xFD")) return "zstd";
  return std::nullopt;
}

}  // namespace polyaxis::io
