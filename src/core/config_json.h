// Reading validated values out of a JSON config document (machine and process files): each getter
// records the first problem, naming the source and the dotted key, as an ErrorCode::kUsage error.
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "polyaxis/core/result.h"

namespace polyaxis::core::detail {

// Config numbers beyond this magnitude are refused as absurd (P5): no axis, feed or offset is a
// thousand kilometres, and larger values would overflow in products.
inline constexpr double kMaxConfigMagnitude = 1e9;

class ConfigReader {
 public:
  explicit ConfigReader(std::string source) : source_(std::move(source)) {}

  // OBJ (at dotted PATH, "" for the root) must be an object holding only keys in ALLOWED.
  bool check_object(const nlohmann::json& obj, std::string_view path, std::initializer_list<std::string_view> allowed);

  bool has(const nlohmann::json& obj, std::string_view key) const { return obj.is_object() && obj.contains(key); }
  double number(const nlohmann::json& obj, std::string_view path, std::string_view key, std::optional<double> fallback);
  std::string string(const nlohmann::json& obj, std::string_view path, std::string_view key,
                     std::optional<std::string> fallback);
  bool boolean(const nlohmann::json& obj, std::string_view path, std::string_view key, std::optional<bool> fallback);

  // Records "KEY_A (a) must not exceed KEY_B (b)" when a > b.
  void require_le(double a, std::string_view key_a, double b, std::string_view key_b);
  void fail(std::string message);  // records MESSAGE (prefixed with the source) unless one is recorded

  bool failed() const { return error_.has_value(); }
  core::Error error() const { return *error_; }
  const std::string& source() const { return source_; }

 private:
  const nlohmann::json* find(const nlohmann::json& obj, std::string_view path, std::string_view key, bool required);

  std::string source_;
  std::optional<core::Error> error_;
};

std::string join_key(std::string_view path, std::string_view key);

// Parses TEXT (comments allowed; duplicate keys refused) or returns kUsage with SOURCE and the
// parser's byte position.
core::Result<nlohmann::json> parse_document(std::string_view text, const std::string& source);

}  // namespace polyaxis::core::detail
