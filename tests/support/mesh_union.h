// Boolean union of closed test meshes (CGAL corefinement), so tests can build parts from
// overlapping primitives the way OpenSCAD does (mesh::unite).
#pragma once

#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::test {

// Union of two closed, outward, non-self-intersecting meshes. Throws std::runtime_error when CGAL
// refuses (a broken test input).
io::RawMesh mesh_union(const io::RawMesh& a, const io::RawMesh& b);

}  // namespace polyaxis::test
