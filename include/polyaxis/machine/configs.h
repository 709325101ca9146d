// The machine and process a job runs with: their files (or the built-in defaults), with KEY=VALUE
// overrides applied, parsed and validated. The CLI's --machine, --process and --set, and the
// Python binding's machine=, process= and sets=, all come here.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::machine {

struct ConfigSources {
  std::string machine_path;       // empty: the built-in 5-axis DED machine (default_machine_json)
  std::string process_path;       // empty: the built-in ded_steel process (process::default_process_json)
  std::vector<std::string> sets;  // "machine.KEY=VALUE" or "process.KEY=VALUE", applied in order
};

struct Configs {
  MachineConfig machine;
  process::ProcessConfig process;
};

// PATH's JSON document (comments allowed, at most 1 MiB), or FALLBACK's (the built-in WHAT) when PATH
// is empty. kUsage naming the file.
core::Result<nlohmann::json> load_config_document(const std::string& path, std::string_view fallback, const char* what);

// Applies overrides: machine.KEY=VALUE to MACHINE, process.KEY=VALUE to PROCESS (kUsage naming the
// override).
core::Status apply_sets(nlohmann::json& machine, nlohmann::json& process, const std::vector<std::string>& sets);

// Loads the files (or the defaults), applies the overrides and validates. Every error is kUsage
// (exit 2) naming the file and key.
core::Result<Configs> load_configs(const ConfigSources& sources);

}  // namespace polyaxis::machine
