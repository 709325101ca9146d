// Separate shells that overlap, united into one solid (mesh/repair.h).
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/self_intersections.h"

namespace polyaxis::mesh {

std::optional<RepairedMesh> unite_overlapping_shells(const RepairedMesh& part) {
  if (part.shells.size() < 2) return std::nullopt;
  std::vector<Mesh> shells;
  for (const Shell& s : part.shells) {
    if (s.cavity || !s.closed) return std::nullopt;
    Mesh m;
    m.vertices = part.mesh.vertices;
    m.triangles.assign(part.mesh.triangles.begin() + s.first_face, part.mesh.triangles.begin() + s.first_face + s.face_count);
    if (!self_intersecting_faces(m).empty()) return std::nullopt;  // a body crossing itself: not a matter of overlap
    shells.push_back(std::move(m));
  }
  auto united = unite(shells);
  if (!united) return std::nullopt;
  auto repaired = repair(io::RawMesh{std::move(united.value().vertices), std::move(united.value().triangles)}, RepairOptions{});
  if (!repaired) return std::nullopt;
  return std::move(repaired.value());
}

}  // namespace polyaxis::mesh
