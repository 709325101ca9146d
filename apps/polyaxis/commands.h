// The CLI's subcommands. Each registers itself on the app and returns a runner that yields the
// process exit code (STYLE.md: 0 ok, 1 internal, 2 usage, 3 invalid input, 4 infeasible,
// 5 machine limit, 6 output I/O).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "polyaxis/core/result.h"

namespace polyaxis::app {

using Runner = std::function<int()>;

Runner add_inspect_command(CLI::App& app);
Runner add_slice_command(CLI::App& app);
Runner add_plan_command(CLI::App& app);
Runner add_simulate_command(CLI::App& app);
Runner add_analyze_command(CLI::App& app);
Runner add_view_command(CLI::App& app);
Runner add_explain_command(CLI::App& app);
Runner add_laminate_command(CLI::App& app);

// Prints ERROR to stderr as "polyaxis: error: ..." and returns its exit code.
int report_error(const core::Error& error);

}  // namespace polyaxis::app
