// --machine, --process and --set, shared by plan and simulate.
#pragma once

#include <CLI/CLI.hpp>

#include "polyaxis/machine/configs.h"

namespace polyaxis::app {

// --machine, --process and --set (machine::load_configs).
using ConfigOptions = machine::ConfigSources;
using machine::Configs;
using machine::apply_sets;
using machine::load_config_document;
using machine::load_configs;

void add_config_options(CLI::App& command, ConfigOptions& options, bool with_process);

}  // namespace polyaxis::app
