// --machine, --process and --set, shared by plan and simulate.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
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

// Loads the files (or the defaults), applies the overrides and validates. Every error is
// kUsage (exit 2) naming the file and key.
core::Result<Configs> load_configs(const ConfigOptions& options);

}  // namespace polyaxis::app
