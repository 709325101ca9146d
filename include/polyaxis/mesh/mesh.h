// The indexed triangle mesh every stage after reading works on.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::mesh {

using core::Vec3;
using io::Triangle;

// Half-edge h = 3·f + k runs from corner k of face f to corner (k+1)%3.
inline constexpr std::uint32_t kNoHalfEdge = 0xffffffffu;

struct Mesh {
  std::vector<Vec3> vertices;        // mm
  std::vector<Triangle> triangles;   // counter-clockwise seen from outside (after repair)

  std::size_t face_count() const { return triangles.size(); }
  Vec3 corner(std::size_t face, int k) const { return vertices[triangles[face][static_cast<std::size_t>(k)]]; }
};

// A connected closed surface of a repaired mesh. Faces of shell s are the contiguous range
// [first_face, first_face + face_count) of Mesh::triangles.
struct Shell {
  std::uint32_t first_face = 0;
  std::uint32_t face_count = 0;
  double volume_mm3 = 0.0;  // signed: > 0 for a solid, < 0 for a cavity
  double area_mm2 = 0.0;
  bool cavity = false;      // an inward-facing shell inside another shell (T8)
  bool closed = true;       // false only when open boundaries were kept (--allow-open)
};

// Twice the area vector of face F (cross product of two edges), mm².
inline Vec3 face_area_vector(const Mesh& mesh, std::size_t face) {
  const Vec3 a = mesh.corner(face, 0);
  return cross(mesh.corner(face, 1) - a, mesh.corner(face, 2) - a);
}

}  // namespace polyaxis::mesh
