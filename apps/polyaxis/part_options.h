// Options shared by every command that reads a part: reading, scaling and repair.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/load_part.h"

namespace polyaxis::app {

// Every number option carries one of these (with its range): CLI11's own number checks let
// "nan" and "inf" through (catalogue P5).
extern const CLI::Validator kFinite;
extern const CLI::Validator kFinitePositive;

// The part's file and how to read and repair it (mesh::load_part).
using PartOptions = mesh::LoadOptions;

void add_part_options(CLI::App& command, PartOptions& options);

// TEXT as a finite number, or kUsage naming WHAT ("--dir: 'x' is not a finite number").
core::Result<double> parse_number(const std::string& text, const std::string& what);

using LoadedPart = mesh::LoadedPart;
using mesh::load_part;

}  // namespace polyaxis::app
