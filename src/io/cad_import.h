// Private: STEP/IGES import through OpenCASCADE, and the result-file protocol between the
// polyaxis-cad-import helper executable (apps/polyaxis-cad-import, the only program that links
// cad_import.cpp and so OpenCASCADE) and read_cad (cad.cpp), which runs that helper under limits
// because OpenCASCADE can crash, hang or exhaust memory on malformed files (F16). This header
// includes no OpenCASCADE header, so cad.cpp can share the protocol constants.
//
// Result file layout (native byte order; the same machine writes and reads it):
//   "PAXCAD1\0", u32 status (0 ok, 1 error),
//   error: u64 length + message bytes;
//   ok:    u64 warning count, each u64 length + bytes; u64 point count, u64 triangle count,
//          points as 3 doubles (mm), triangles as 3 u32.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::io {

namespace cad_protocol {

inline constexpr char kMagic[8] = {'P', 'A', 'X', 'C', 'A', 'D', '1', '\0'};
inline constexpr std::uint32_t kStatusOk = 0;
inline constexpr std::uint32_t kStatusError = 1;

// Helper exit codes.
inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;          // bad command line (a bug in read_cad)
inline constexpr int kExitImportError = 3;    // an Error was written
inline constexpr int kExitWriteFailed = 4;    // the result file could not be written
inline constexpr int kExitException = 5;      // something escaped the importer's own catch
inline constexpr int kExitOutOfMemory = 6;    // std::bad_alloc escaped (RLIMIT_AS reached)
inline constexpr int kExitCannotLoad = 127;   // the dynamic loader could not start the helper

}  // namespace cad_protocol

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

// Runs import_cad_file and writes its outcome to RESULT_FD (an empty, writable file, positioned at
// its start) in the layout above. Returns the exit code the helper should end with
// (cad_protocol::kExit*): kExitOk, kExitImportError (the Error was written), kExitWriteFailed,
// kExitOutOfMemory or kExitException. Never throws. Cost: the import plus one pass of 64 KiB writes.
int import_cad_to_fd(int result_fd, const std::string& path, Format format, double chordal_mm, double angular_deg);

}  // namespace polyaxis::io
