// Private: STEP/IGES import through OpenCASCADE, in the calling process. The only file that
// includes OpenCASCADE headers is cad_import.cpp; callers (cad.cpp) run this in a child process,
// because OpenCASCADE can crash, hang or exhaust memory on malformed files (F16).
#pragma once

#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::io {

// Reads PATH as FORMAT (kStep or kIges; anything else is an Error), transfers every root into one
// shape, meshes its faces with BRepMesh to CHORDAL_MM (absolute deflection, mm) and ANGULAR_DEG,
// and returns the triangles of every face with the face location applied and reversed faces
// flipped, so a closed solid comes out outward-oriented. Nodes are shared within a face, not
// between faces (repair merges them). Coordinates are in millimetres (OpenCASCADE converts the
// file's unit). Errors (kInvalidInput) say "STEP import failed: ..." (or "IGES ..."). A file with
// surfaces but no solid is imported, with a warning appended to WARNINGS (if not null): the mesh
// may be open. Never lets an OpenCASCADE exception escape; cannot protect against its crashes.
core::Result<RawMesh> import_cad_file(const std::string& path, Format format, double chordal_mm,
                                      double angular_deg, std::vector<std::string>* warnings = nullptr);

}  // namespace polyaxis::io
