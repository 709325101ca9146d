// --machine, --process and --set, shared by plan and simulate.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::app {

struct ConfigOptions {
  std::string machine_path;          // empty: the embedded 5-axis DED machine
  std::string process_path;          // empty: the embedded ded_steel process
  std::vector<std::string> sets;     // machine.KEY=VALUE or process.KEY=VALUE
};

void add_config_options(CLI::App& command, ConfigOptions& options, bool with_process);

struct Configs {
  machine::MachineConfig machine;
  process::ProcessConfig process;
};

// PATH's JSON document (comments allowed), or FALLBACK's (the built-in WHAT) when PATH is empty.
// kUsage naming the file.
core::Result<nlohmann::json> load_config_document(const std::string& path, std::string_view fallback, const char* what);
// Applies --set overrides: machine.KEY=VALUE to MACHINE, process.KEY=VALUE to PROCESS (kUsage
// naming the override).
core::Status apply_sets(nlohmann::json& machine, nlohmann::json& process, const std::vector<std::string>& sets);

// Loads the files (or the defaults), applies the overrides and validates. Every error is
// kUsage (exit 2) naming the file and key.
core::Result<Configs> load_configs(const ConfigOptions& options);

}  // namespace polyaxis::app
