// Cutting a closed mesh in two by a plane, capping both halves (CGAL corefinement).
#pragma once

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

struct PlaneCut {
  Mesh below;  // the solid where (p − point)·normal <= 0, closed (capped on the plane)
  Mesh above;  // the solid where (p − point)·normal >= 0, closed
};

// Precondition: MESH closed, manifold, outward and free of self-intersections (repair output).
// Either side may be empty when the plane misses the part. Error kInfeasible when CGAL cannot
// cut (a self-intersecting input). Cost: O(F log F) (corefinement with the plane's box).
core::Result<PlaneCut> cut_by_plane(const Mesh& mesh, core::Vec3 point, core::Vec3 normal);

}  // namespace polyaxis::mesh
