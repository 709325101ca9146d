// What every reader returns: an indexed triangle soup in millimetres, before any repair.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/core/vec3.h"

namespace polyaxis::io {

using Triangle = std::array<std::uint32_t, 3>;

// Points are finite (readers refuse NaN/Inf with the facet named); every index is < points.size().
// Bit-identical points are already shared (STL has no indices); nothing else is merged here.
struct RawMesh {
  std::vector<core::Vec3> points;
  std::vector<Triangle> triangles;
};

enum class Format { kStlBinary, kStlAscii, kObj, k3mf, kStep, kIges };

std::string_view format_name(Format format);  // "stl-binary", "stl-ascii", "obj", "3mf", "step", "iges"

// A reader's value: the mesh plus what it noticed and worked around (exit 0 with warnings).
struct ReadResult {
  Format format = Format::kStlBinary;
  RawMesh mesh;
  std::vector<std::string> warnings;
};

}  // namespace polyaxis::io
