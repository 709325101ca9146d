// A closed tube swept along a polyline: the solid a branch of a part's skeleton stands for.
#pragma once

#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

// The surface of the balls of RADII (mm, > 0) centred at AXIS's points swept along it: a ring of
// SIDES points around each point of AXIS, in the plane normal to the axis there (frames carried
// along by parallel transport), and a hemisphere of QUARTER_RINGS rings at each end. Closed,
// outward, manifold. It crosses itself where the axis turns more sharply than the radius (a bend
// whose radius is below the tube's) or comes back near itself; callers check
// (self_intersecting_faces) before using it as a solid. Preconditions: AXIS.size() == RADII.size()
// >= 2, consecutive points distinct, SIDES >= 3, QUARTER_RINGS >= 1. Cost: O(|AXIS| · SIDES).
Mesh tube(const std::vector<Vec3>& axis, const std::vector<double>& radii, int sides = 32, int quarter_rings = 4);

}  // namespace polyaxis::mesh
