// Writing a mesh as binary STL (for region files and test data).
#pragma once

#include <string>

#include "polyaxis/io/raw_mesh.h"

namespace polyaxis::io {

// Binary STL bytes of MESH: an 80-byte header holding NAME, the count, then one record per
// triangle with its unit normal (computed) and corners as float32.
std::string binary_stl(const RawMesh& mesh, const std::string& name);

}  // namespace polyaxis::io
