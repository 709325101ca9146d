// Distance from points to a triangle surface, and the refinement that lets a field sampled at a
// mesh's corners follow a curved base: what conformal layers (slicing/conformal.h) are made of.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <memory>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

// The point of a surface nearest to a query point, and the signed distance to it: positive outside
// a closed outward mesh, negative inside. The sign is taken against the angle-weighted pseudonormal
// of the feature the nearest point lies on (Bærentzen & Aanæs): the face's normal inside a face,
// the sum of its two faces' normals on an edge, the angle-weighted sum of its faces' normals at a
// vertex, which is right wherever the nearest point lies.
struct Nearest {
  Vec3 point;
  double signed_mm = 0.0;
  Vec3 normal{0, 0, 1};  // unit, the pseudonormal at POINT
  std::uint32_t face = 0;  // the surface's triangle POINT lies on (one of them on an edge or a vertex)
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
  // The same, starting the search from NEAR, the answer for a point close to P (the step before of
  // an iteration, the point before along a path): the tree is searched within the distance to it
  // rather than from the surface's nearest vertex, which on long thin triangles (a turned part's
  // sides) lies far from the nearest point. NEAR: a result of this surface's nearest().
  Nearest nearest(Vec3 p, const Nearest& near) const;

 private:
  // The answer for P whose nearest point POINT lies on triangle FACE: its feature's pseudonormal, the sign.
  Nearest described(Vec3 p, Vec3 point, std::size_t face) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// MESH with every edge longer than MAX_EDGE_MM bisected, longest edge first (Rivara), each split
// applied to both faces of the edge, so a closed manifold mesh stays closed and manifold and the
// faces keep their orientation. MAX_EDGE_MM > 0. Cost: O(F' log F') for the F' faces made.
Mesh refine(const Mesh& mesh, double max_edge_mm);

// The same with the edges to bisect chosen by SPLIT(a, b) (each face's longest edge that SPLIT
// takes is bisected, until none is); nullopt when that would make more than MAX_FACES faces.
std::optional<Mesh> refine(const Mesh& mesh, const std::function<bool(Vec3 a, Vec3 b)>& split, std::size_t max_faces);

}  // namespace polyaxis::mesh
