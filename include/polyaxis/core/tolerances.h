// Every tolerance polyaxis uses, with its unit and its reason, in one place.
#pragma once

#include <cstdint>

namespace polyaxis::core {

// Vertices closer than this are one vertex (repair, T9). 0.1 µm: far below any deposition or
// cutting resolution, and above the float rounding of STL coordinates (~8 nm at 100 mm).
inline constexpr double kVertexMergeMm = 1e-4;

// A triangle whose area is below this is degenerate (repair, T5). (0.1 µm)² scale; exactly zero
// area (collinear or repeated vertices) is always degenerate.
inline constexpr double kDegenerateAreaMm2 = 1e-10;

// Coordinates beyond this are refused (F7): no machine is a kilometre wide, and larger values lose
// the 1 nm integer snapping of geom2d.
inline constexpr double kMaxCoordinateMm = 1e6;

// A part whose largest extent is below this is probably in metres (F8).
inline constexpr double kTinyPartMm = 1e-3;
// A part whose largest extent is below this, with every extent tiny, may be in metres or inches.
inline constexpr double kSuspectMetresMm = 2.0;
// A part larger than this is probably in micrometres (F8).
inline constexpr double kSuspectMicronsMm = 1e5;

// Default self-supporting angle from vertical, degrees (Kapil: about 30° for mild steel).
inline constexpr double kDefaultSelfSupportingDeg = 30.0;

// Default cap on triangles accepted from any reader (F10), checked before allocating.
inline constexpr std::uint64_t kDefaultMaxTriangles = 50'000'000;

// Holes with at most this many boundary edges are filled by default (T1).
inline constexpr std::uint32_t kDefaultMaxHoleEdges = 64;

// Default chordal tolerance for tessellating STEP/IGES surfaces, mm.
inline constexpr double kDefaultChordalMm = 0.01;

// Decompression cap for 3MF archives (F15: zip bombs): total uncompressed bytes and ratio.
inline constexpr std::uint64_t kMax3mfUncompressedBytes = 2ull << 30;
inline constexpr double kMax3mfCompressionRatio = 1000.0;

// A generalized winding number above this counts a point as inside a closed shell (exact value 1).
inline constexpr double kInsideWindingNumber = 0.5;

}  // namespace polyaxis::core
