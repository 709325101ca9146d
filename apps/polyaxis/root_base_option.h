// --root-base z-min|FACE-ID|PX,PY,PZ,NX,NY,NZ for `analyze` and `plan --decompose`.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "polyaxis/analysis/decompose.h"
#include "polyaxis/core/result.h"

namespace polyaxis::app {

void add_root_base_option(CLI::App& cmd, std::string& text);

// TEXT as a RootBase: "" (auto), "z-min", a face id, or a plane "px,py,pz,nx,ny,nz" (a point and
// the root's build direction). kUsage naming --root-base otherwise.
core::Result<analysis::RootBase> parse_root_base(const std::string& text);

}  // namespace polyaxis::app
