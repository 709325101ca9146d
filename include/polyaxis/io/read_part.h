// Reading a part file of any supported format. The only entry point the CLI needs.
#pragma once

#include <cstdint>
#include <string>

#include "polyaxis/core/result.h"
#include "polyaxis/core/tolerances.h"
#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::io {

struct ReadOptions {
  std::uint64_t max_triangles = core::kDefaultMaxTriangles;  // F10: refused before allocating
  double chordal_mm = core::kDefaultChordalMm;  // STEP/IGES tessellation: max chord deviation, mm
  double angular_deg = 20.0;                    // STEP/IGES tessellation: max angle between normals
  bool strict = false;                          // warnings that drop geometry become errors (F15)
  double import_timeout_s = 300.0;              // STEP/IGES child process: wall-clock limit
  std::uint64_t import_memory_bytes = 8ull << 30;  // STEP/IGES child process: address-space limit
};

// Reads PATH, choosing the format by extension (.stl .obj .3mf .step .stp .iges .igs, any case) and,
// for an unknown extension, by content. Refuses at once (exit class kInvalidInput) directories,
// FIFOs, devices, unreadable and compressed files (F11, F17). Cost: one pass over the file; memory
// about 36 bytes per distinct point + 12 per triangle (the file itself is mapped, not copied).
core::Result<ReadResult> read_part(const std::string& path, const ReadOptions& options = {});

}  // namespace polyaxis::io
