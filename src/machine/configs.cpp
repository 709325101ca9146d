#include "polyaxis/machine/configs.h"

#include <fmt/format.h>

#include "polyaxis/core/config_document.h"
#include "polyaxis/io/text_file.h"

namespace polyaxis::machine {
namespace {

constexpr std::uint64_t kMaxConfigBytes = 1 << 20;

}  // namespace

core::Result<nlohmann::json> load_config_document(const std::string& path, std::string_view fallback, const char* what) {
  std::string text(fallback);
  std::string source = fmt::format("the built-in {}", what);
  if (!path.empty()) {
    auto read = io::read_text_file(path, kMaxConfigBytes);
    if (!read) return core::make_error(core::ErrorCode::kUsage, read.error().message);
    text = std::move(read.value());
    source = path;
  }
  return core::parse_config_document(text, source);
}

core::Status apply_sets(nlohmann::json& machine, nlohmann::json& process, const std::vector<std::string>& sets) {
  for (const std::string& set : sets) {
    core::Status s;
    if (set.starts_with("machine.")) {
      s = core::apply_override(machine, std::string_view(set).substr(8));
    } else if (set.starts_with("process.")) {
      s = core::apply_override(process, std::string_view(set).substr(8));
    } else {
      return core::make_error(core::ErrorCode::kUsage, fmt::format("--set {}: say machine.KEY=VALUE or process.KEY=VALUE", set));
    }
    if (!s) return core::make_error(core::ErrorCode::kUsage, fmt::format("--set {}: {}", set, s.error().message));
  }
  return {};
}

core::Result<Configs> load_configs(const ConfigSources& options) {
  auto machine_doc = load_config_document(options.machine_path, default_machine_json(), "machine");
  if (!machine_doc) return machine_doc.error();
  auto process_doc = load_config_document(options.process_path, process::default_process_json(), "process");
  if (!process_doc) return process_doc.error();
  if (auto s = apply_sets(machine_doc.value(), process_doc.value(), options.sets); !s) return s.error();
  Configs configs;
  auto machine = parse_machine(machine_doc.value().dump(), options.machine_path.empty() ? "the built-in machine" : options.machine_path);
  if (!machine) return machine.error();
  configs.machine = std::move(machine.value());
  auto process = process::parse_process(process_doc.value().dump(), options.process_path.empty() ? "the built-in process" : options.process_path);
  if (!process) return process.error();
  configs.process = std::move(process.value());
  return configs;
}

}  // namespace polyaxis::machine
