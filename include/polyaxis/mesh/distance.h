// Distance from points to a triangle surface, and the refinement that lets a field sampled at a
// mesh's corners follow a curved base: what conformal layers (slicing/conformal.h) are made of.
#pragma once

#include <memory>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

// The point of a surface nearest to a query point, and the signed distance to it: positive on the
// side the nearest face's normal points to (outside a closed outward mesh), negative behind it.
struct Nearest {
  Vec3 point;
  double signed_mm = 0.0;
  Vec3 normal{0, 0, 1};  // unit, of the face holding POINT
};

// An AABB tree (CGAL) over the triangles of a surface, built once; queries are thread-safe.
class SurfaceDistance {
 public:
  // SURFACE: any triangles (closed or not); degenerate faces are skipped. Cost: O(F log F).
  explicit SurfaceDistance(const Mesh& surface);
  ~SurfaceDistance();
  SurfaceDistance(const SurfaceDistance&) = delete;
  SurfaceDistance& operator=(const SurfaceDistance&) = delete;

  bool empty() const;
  // Precondition: !empty(). Cost: O(log F) on average.
  Nearest nearest(Vec3 p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// MESH with every edge longer than MAX_EDGE_MM bisected, longest edge first (Rivara), each split
// applied to both faces of the edge, so a closed manifold mesh stays closed and manifold and the
// faces keep their orientation. MAX_EDGE_MM > 0. Cost: O(F' log F') for the F' faces made.
Mesh refine(const Mesh& mesh, double max_edge_mm);

}  // namespace polyaxis::mesh
