// Machine and process files as JSON documents, before they are parsed into their configs: the
// document itself (comments allowed, duplicate keys refused) and dotted `key=value` overrides.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "polyaxis/core/result.h"

namespace polyaxis::core {

// Parses JSON config text into a document (comments allowed, duplicate keys refused), for callers
// that apply --set overrides before parse_machine / parse_process. Errors are kUsage.
core::Result<nlohmann::json> parse_config_document(std::string_view json, const std::string& source);

// Applies one `--set key=value` override: KEY is dotted (`limits.c.max=360`) and must name a value
// already present in DOC (files and the embedded defaults spell every key out); VALUE is parsed as
// JSON when the existing value is a number or a boolean, and taken verbatim when it is a string.
// Unknown key or a value of the wrong type → kUsage naming the key. DOC is untouched on error.
core::Status apply_override(nlohmann::json& doc, std::string_view key_eq_value);

}  // namespace polyaxis::core
