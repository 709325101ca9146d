// A bound on the nesting of JSON text, checked before it is parsed: nlohmann's parser and the
// documents it builds recurse with the nesting, so 60 000 nested arrays overflow the stack (R14.1).
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace polyaxis::core {

// No machine file, process file or plan nests deeper than a dozen levels.
inline constexpr std::size_t kMaxJsonDepth = 64;

// The byte offset where TEXT opens its (MAX_DEPTH + 1)-th nested array or object; none when it
// never nests deeper than MAX_DEPTH. Brackets inside strings (with their escapes) do not count.
inline std::optional<std::size_t> json_too_deep(std::string_view text, std::size_t max_depth = kMaxJsonDepth) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::nullopt;
}

}  // namespace polyaxis::core
