// Faces of a mesh that intersect another face other than along their shared edge or vertex.
// CGAL: box_intersection_d to find candidate pairs, exact predicates (Epick) to decide them.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

// Sorted indices of the faces that take part in at least one intersection. Faces must be
// non-degenerate. Cost: O(n log n + k) for k candidate pairs whose boxes overlap.
std::vector<std::uint32_t> self_intersecting_faces(const Mesh& mesh);

}  // namespace polyaxis::mesh
