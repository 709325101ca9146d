// A part as every command and binding takes it: read (io::read_part), scaled, then repaired
// (mesh::repair). The one place that chain lives, so that the CLI, the library and the Python
// binding give the same mesh for the same file and options.
#pragma once

#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"

namespace polyaxis::mesh {

struct LoadOptions {
  std::string path;      // STL, OBJ, 3MF, STEP or IGES (io::read_part)
  double scale = 1.0;    // every coordinate is multiplied by it (1000 for metres, 25.4 for inches); finite, > 0
  io::ReadOptions read;  // read.strict is taken from repair.strict
  RepairOptions repair;  // repair.strict also turns the self-intersection check on
};

// Everything known about a part after reading and repair.
struct LoadedPart {
  io::Format format = io::Format::kStlBinary;
  RepairedMesh repaired;
  std::vector<std::string> warnings;  // the reader's and repair's, one line each
  double read_s = 0.0;                // wall time of reading, s
  double repair_s = 0.0;              // wall time of repair, s
};

// Reads, scales and repairs OPTIONS.path. Errors are io::read_part's and mesh::repair's (the
// latter prefixed with the path), each carrying its exit class; a scale that is not finite and
// positive is kUsage.
core::Result<LoadedPart> load_part(const LoadOptions& options);

// The same from a triangle soup already in memory (the Python binding's arrays), checked as a
// reader checks a file: a point that is not finite or an index out of range is kInvalidInput
// naming it. OPTIONS.path is not read; NAME stands for it in messages.
core::Result<LoadedPart> load_part(io::RawMesh mesh, const LoadOptions& options, const std::string& name);

}  // namespace polyaxis::mesh
