#include "core/config_json.h"
#include "polyaxis/core/config_document.h"
#include "polyaxis/core/json_depth.h"

#include <fmt/format.h>

#include <cmath>
#include <set>
#include <vector>

namespace polyaxis::core::detail {

using nlohmann::json;

std::string join_key(std::string_view path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

void ConfigReader::fail(std::string message) {
  if (!error_) error_ = core::make_error(core::ErrorCode::kUsage, fmt::format("{}: {}", source_, message));
}

bool ConfigReader::check_object(const json& obj, std::string_view path, std::initializer_list<std::string_view> allowed) {
  if (!obj.is_object()) {
    fail(fmt::format("{} must be an object", path.empty() ? "the document" : path));
    return false;
  }
  for (const auto& [key, value] : obj.items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || a == key;
    if (!known) {
      fail(fmt::format("unknown key '{}' (expected one of: {})", join_key(path, key), fmt::join(allowed, ", ")));
      return false;
    }
  }
  return true;
}

const json* ConfigReader::find(const json& obj, std::string_view path, std::string_view key, bool required) {
  if (obj.is_object()) {
    const auto it = obj.find(key);
    if (it != obj.end()) return &*it;
  }
  if (required) fail(fmt::format("missing key '{}'", join_key(path, key)));
  return nullptr;
}

double ConfigReader::number(const json& obj, std::string_view path, std::string_view key, std::optional<double> fallback) {
  const json* v = find(obj, path, key, !fallback.has_value());
  if (v == nullptr) return fallback.value_or(0.0);
  if (!v->is_number()) {
    fail(fmt::format("'{}' must be a number, not {}", join_key(path, key), v->dump()));
    return 0.0;
  }
  const double d = v->get<double>();
  // nlohmann parses 1e999 as inf; JSON has no nan literal but a computed document may (P5).
  if (!std::isfinite(d)) {
    fail(fmt::format("'{}' is not a finite number ({})", join_key(path, key), d));
    return 0.0;
  }
  if (std::abs(d) > kMaxConfigMagnitude) {
    fail(fmt::format("'{}' = {} is out of range (|value| ≤ {})", join_key(path, key), d, kMaxConfigMagnitude));
    return 0.0;
  }
  return d;
}

std::string ConfigReader::string(const json& obj, std::string_view path, std::string_view key,
                                 std::optional<std::string> fallback) {
  const json* v = find(obj, path, key, !fallback.has_value());
  if (v == nullptr) return fallback.value_or(std::string());
  if (!v->is_string()) {
    fail(fmt::format("'{}' must be a string, not {}", join_key(path, key), v->dump()));
    return {};
  }
  return v->get<std::string>();
}

bool ConfigReader::boolean(const json& obj, std::string_view path, std::string_view key, std::optional<bool> fallback) {
  const json* v = find(obj, path, key, !fallback.has_value());
  if (v == nullptr) return fallback.value_or(false);
  if (!v->is_boolean()) {
    fail(fmt::format("'{}' must be true or false, not {}", join_key(path, key), v->dump()));
    return false;
  }
  return v->get<bool>();
}

void ConfigReader::require_le(double a, std::string_view key_a, double b, std::string_view key_b) {
  if (a > b) fail(fmt::format("'{}' ({}) must not exceed '{}' ({})", key_a, a, key_b, b));
}

core::Result<json> parse_document(std::string_view text, const std::string& source) {
  // nlohmann keeps the last of duplicate keys silently; a duplicate is a typo as much as an
  // unknown key (P6), so the parser callback tracks the keys of every open object.
  // The path of the key being read (for messages) is kept the same way: nlohmann refuses 1e999
  // ("number overflow") as a parse error, and the message should still name the key (P5).
  std::vector<std::set<std::string>> open_objects;
  std::vector<std::string> path;
  std::string duplicate;
  const json::parser_callback_t track = [&](int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        open_objects.emplace_back();
        path.emplace_back();
        break;
      case json::parse_event_t::array_start: path.emplace_back("[]"); break;
      case json::parse_event_t::object_end:
        if (!open_objects.empty()) open_objects.pop_back();
        if (!path.empty()) path.pop_back();
        break;
      case json::parse_event_t::array_end:
        if (!path.empty()) path.pop_back();
        break;
      case json::parse_event_t::key:
        if (!path.empty()) path.back() = parsed.get<std::string>();
        if (!open_objects.empty() && !open_objects.back().insert(parsed.get<std::string>()).second &&
            duplicate.empty()) {
          duplicate = parsed.get<std::string>();
        }
        break;
      default: break;
    }
    return true;
  };
  if (const auto at = core::json_too_deep(text)) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("{}: not valid JSON: nested deeper than {} levels at byte {}", source,
                                                                 core::kMaxJsonDepth, *at));
  }
  json doc;
  try {
    doc = json::parse(text.begin(), text.end(), track, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const json::exception& e) {
    std::string where;
    for (const std::string& k : path) {
      if (!k.empty()) where = join_key(where, k);
    }
    return core::make_error(core::ErrorCode::kUsage, fmt::format("{}: not valid JSON{}: {}", source,
                                                                 where.empty() ? "" : " at '" + where + "'", e.what()));
  }
  if (!duplicate.empty()) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("{}: key '{}' appears twice in one object", source, duplicate));
  }
  return doc;
}

}  // namespace polyaxis::core::detail

namespace polyaxis::core {

using nlohmann::json;

core::Result<json> parse_config_document(std::string_view text, const std::string& source) {
  return detail::parse_document(text, source);
}

namespace {

// True when TEXT is well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF).
bool valid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      n = 1, cp = c & 0x1F;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 2, cp = c & 0x0F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 3, cp = c & 0x07;
    } else {
      return false;
    }
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= text.size()) return false;
      const auto d = static_cast<unsigned char>(text[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3F);
    }
    if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += n + 1;
  }
  return true;
}

}  // namespace

core::Status apply_override(json& doc, std::string_view key_eq_value) {
  auto usage = [&](const std::string& why) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("--set {}: {}", key_eq_value, why));
  };
  const std::size_t eq = key_eq_value.find('=');
  if (eq == std::string_view::npos || eq == 0) return usage("expected key=value, e.g. limits.c.max=360");
  const std::string_view key = key_eq_value.substr(0, eq);
  const std::string_view value = key_eq_value.substr(eq + 1);

  json* node = &doc;
  std::string walked;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string part(key.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
    if (!node->is_object() || !node->contains(part)) {
      std::vector<std::string> known;
      if (node->is_object()) {
        for (const auto& [k, v] : node->items()) known.push_back(k);
      }
      return usage(fmt::format("unknown key '{}' (known{}: {})", detail::join_key(walked, part),
                               walked.empty() ? "" : " under " + walked, fmt::join(known, ", ")));
    }
    node = &(*node)[part];
    walked = detail::join_key(walked, part);
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  if (node->is_object()) return usage(fmt::format("'{}' is a group of keys, not a value", walked));
  // JSON text is UTF-8: a value that is not would make the document unwritable (it was an
  // internal error, exit 1, found by fuzz_config).
  if (!valid_utf8(value)) return usage(fmt::format("'{}': the value is not valid UTF-8", walked));
  if (node->is_string()) {
    *node = std::string(value);
    return {};
  }
  json parsed;
  try {
    parsed = json::parse(value);
  } catch (const json::exception&) {
    return usage(fmt::format("'{}' needs a {} value, not '{}'", walked, node->is_boolean() ? "true/false" : "number", value));
  }
  if (node->is_boolean() != parsed.is_boolean() || node->is_number() != parsed.is_number()) {
    return usage(fmt::format("'{}' needs a {} value, not '{}'", walked, node->is_boolean() ? "true/false" : "number", value));
  }
  *node = std::move(parsed);
  return {};
}

}  // namespace polyaxis::core
