#include "mesh_union.h"

#include <stdexcept>

#include "polyaxis/mesh/plane_cut.h"

namespace polyaxis::test {

io::RawMesh mesh_union(const io::RawMesh& a, const io::RawMesh& b) {
  auto out = mesh::unite({mesh::Mesh{a.points, a.triangles}, mesh::Mesh{b.points, b.triangles}});
  if (!out) throw std::runtime_error("mesh_union: " + out.error().message);
  return io::RawMesh{out.value().vertices, out.value().triangles};
}

}  // namespace polyaxis::test
