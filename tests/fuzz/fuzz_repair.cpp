// libFuzzer target: repair of a structured triangle soup. The bytes give a vertex count, small
// integer coordinates (so coincidences, degeneracies and non-manifold edges are common) and
// triangle indices. Invariants after a successful repair: every index in range; no edge with
// more than two faces; closed unless open holes were kept; shells partition the faces.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  if (size < 2) return 0;
  io::RawMesh raw;
  const std::size_t nv = 3 + data[0] % 29;
  std::size_t pos = 1;
  for (std::size_t i = 0; i < nv && pos + 3 <= size; ++i, pos += 3) {
    raw.points.push_back({static_cast<double>(data[pos] % 8), static_cast<double>(data[pos + 1] % 8),
                          static_cast<double>(data[pos + 2] % 8)});
  }
  if (raw.points.size() < 3) return 0;
  const auto n = static_cast<std::uint32_t>(raw.points.size());
  for (; pos + 3 <= size && raw.triangles.size() < 400; pos += 3) {
    raw.triangles.push_back({data[pos] % n, data[pos + 1] % n, data[pos + 2] % n});
  }
  if (raw.triangles.empty()) return 0;
  mesh::RepairOptions options;
  options.allow_open = (data[0] & 0x80) != 0;
  auto r = mesh::repair(raw, options);
  if (!r) return 0;
  const mesh::Mesh& m = r.value().mesh;
  for (const auto& t : m.triangles) {
    for (auto v : t) {
      if (v >= m.vertices.size()) std::abort();
    }
  }
  const mesh::EdgeTopology topo = mesh::build_topology(m);
  if (topo.nonmanifold_edges != 0) std::abort();
  if (r.value().report.open_holes == 0 && topo.boundary_edges != 0) std::abort();
  std::size_t faces = 0;
  for (const auto& s : r.value().shells) {
    if (s.first_face != faces) std::abort();
    faces += s.face_count;
  }
  if (faces != m.triangles.size()) std::abort();
  return 0;
}
