// Options shared by every command that reads a part: reading, scaling and repair.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"

namespace polyaxis::app {

// Every number option carries one of these (with its range): CLI11's own number checks let
// "nan" and "inf" through (catalogue P5).
extern const CLI::Validator kFinite;
extern const CLI::Validator kFinitePositive;

struct PartOptions {
  std::string path;
  double scale = 1.0;
  io::ReadOptions read;
  mesh::RepairOptions repair;
};

void add_part_options(CLI::App& command, PartOptions& options);

// TEXT as a finite number, or kUsage naming WHAT ("--dir: 'x' is not a finite number").
core::Result<double> parse_number(const std::string& text, const std::string& what);

// Everything a command knows about a part after reading and repair.
struct LoadedPart {
  io::Format format = io::Format::kStlBinary;
  mesh::RepairedMesh repaired;
  std::vector<std::string> warnings;  // reader's and repair's, one line each
  double read_s = 0.0;
  double repair_s = 0.0;
};

// Reads, scales and repairs OPTIONS.path. Errors carry the exit class.
core::Result<LoadedPart> load_part(const PartOptions& options);

}  // namespace polyaxis::app
