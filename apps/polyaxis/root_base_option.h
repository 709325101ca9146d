// --root-base z-min|FACE-ID|PX,PY,PZ,NX,NY,NZ for `analyze` and `plan --decompose`.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "polyaxis/analysis/root_base.h"

namespace polyaxis::app {

void add_root_base_option(CLI::App& cmd, std::string& text);

using analysis::parse_root_base;

}  // namespace polyaxis::app
