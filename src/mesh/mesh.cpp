#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

Vec3 face_area_vector(const Mesh& mesh, std::size_t face) {
  const Vec3 a = mesh.corner(face, 0);
  return cross(mesh.corner(face, 1) - a, mesh.corner(face, 2) - a);
}

}  // namespace polyaxis::mesh
