// Faces of a mesh that intersect another face other than along their shared edge or vertex.
// Candidate pairs from a uniform grid (in parallel; CGAL's box_intersection_d for uneven meshes),
// exact predicates (Epick) to decide them. Neighbouring faces (a shared vertex or edge: most of the
// candidates) are first cleared by a proof per vertex that its fan projects one to one onto a
// plane, with margins well above rounding; the pairs it cannot clear are decided exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::mesh {

// Sorted indices of the faces that take part in at least one intersection. Faces must be
// non-degenerate. TOPOLOGY: the mesh's, when the caller has it (else it is built). Cost: O(n + k)
// for k candidate pairs whose boxes overlap, on two cores or more in parallel.
std::vector<std::uint32_t> self_intersecting_faces(const Mesh& mesh, const EdgeTopology* topology = nullptr);

namespace detail {
// The same answer with CGAL's box_intersection_d for the candidates (the fallback for uneven
// meshes) and every pair decided by the exact predicates, for tests to hold the grid and the fan
// proof against.
std::vector<std::uint32_t> self_intersecting_faces_by_boxes(const Mesh& mesh);
}  // namespace detail

}  // namespace polyaxis::mesh
