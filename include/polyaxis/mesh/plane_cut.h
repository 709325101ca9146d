// Cutting a closed mesh in two by a plane, capping both halves, and joining pieces back into one
// solid (CGAL corefinement, exact constructions).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

struct PlaneCut {
  Mesh below;  // the solid where (p − point)·normal <= 0, closed (capped on the plane)
  Mesh above;  // the solid where (p − point)·normal >= 0, closed
};

// Precondition: MESH closed, manifold, outward and free of self-intersections (repair output).
// Either side may be empty when the plane misses the part. Error kInfeasible when CGAL cannot
// cut (a self-intersecting input), and, checked first, when the plane meets a face that crosses
// another (CGAL's clip is undefined there; it crashed): faces that cross away from the plane are
// cut around. Cost: O(F log F) (corefinement with the plane's box; the crossing faces' search).
core::Result<PlaneCut> cut_by_plane(const Mesh& mesh, core::Vec3 point, core::Vec3 normal);

struct CutOff {
  Mesh child;   // one connected piece on the normal side of the plane, closed
  Mesh parent;  // everything else: the other side and the other pieces on the normal side, as one solid
  // The other pieces are glued back along the caps they share with the other side (both caps
  // dropped, the borders stitched, exactly); those that cannot be are united by corefinement,
  // which intersects the coplanar caps in exact rationals (a coil spring's analysis: 8.6 s by
  // corefinement, 1.6 s glued). How many were united that way.
  std::size_t united_pieces = 0;
};

// Chooses the child among the connected pieces on the normal side (in the order given), by index,
// or refuses them all (nothing is cut off; the parent is not built).
using PiecePicker = std::function<std::optional<std::size_t>(const std::vector<Mesh>& pieces)>;

// Cuts MESH by the plane (POINT, NORMAL) and takes off as the child the piece on the normal side
// that PICK chooses; the parent is the rest, the other side with the other pieces put back onto
// it (in exact arithmetic, so the caps they share vanish instead of doubling). Preconditions as
// cut_by_plane. Error kInfeasible when the plane leaves either side empty or CGAL cannot cut or
// unite (pieces meeting the rest along an edge only, or more than 3 pieces besides the child), or
// when PICK refuses. Cost: O(F log F) per piece.
core::Result<CutOff> cut_off(const Mesh& mesh, core::Vec3 point, core::Vec3 normal, const PiecePicker& pick);

// The union of closed, outward, non-self-intersecting PIECES as one mesh: pieces touching along
// faces become one solid, with no doubled faces (the faces must match exactly: coordinates already
// rounded from one cut's caps may not, see cut_off).
// Error kInfeasible when CGAL cannot (the result would not be a manifold: pieces meeting along an
// edge or a point only). Cost: O(F log F) per piece.
core::Result<Mesh> unite(const std::vector<Mesh>& pieces);

// A less B (closed, outward, non-self-intersecting): the solid of A outside B, closed; empty when
// B holds all of A, A itself when they do not meet. Error kInfeasible when CGAL cannot (a result
// that would not be a manifold, such as solids meeting along an edge only). Cost: O(F log F).
core::Result<Mesh> difference(const Mesh& a, const Mesh& b);

// A and B's common solid (closed, outward, non-self-intersecting): closed; empty when they do not
// meet. Errors and cost as difference().
core::Result<Mesh> intersection(const Mesh& a, const Mesh& b);

// The surface of the solid that MESH (closed, outward) bounds where its faces cross one another:
// the faces are split along their crossings and the parts inside the solid dropped (CGAL's
// autorefinement). Meant for a surface grown() a little, whose faces cross where it was folded
// fine (slivers along the seam of a union), before it is used in difference(). MESH itself when
// no faces cross. Error kInfeasible when CGAL cannot remove every crossing. Cost: O(F log F).
core::Result<Mesh> without_crossings(const Mesh& mesh);

// MESH with every vertex moved BY_MM along its angle-weighted normal (outwards for an outward
// mesh; inwards for a negative BY_MM): a smooth surface moves by BY_MM, faces meeting at an edge or
// a corner less (a cube's faces by BY_MM/√3). Meant for small offsets, below half the thinnest
// feature (larger ones can fold the surface). Cost: O(F).
Mesh grown(const Mesh& mesh, double by_mm);

}  // namespace polyaxis::mesh
