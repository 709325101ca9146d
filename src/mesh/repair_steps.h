// The passes of repair(), in the order repair.cpp runs them. Private to the mesh module.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::mesh::detail {

// Merges the CANDIDATES (ascending vertex ids) that lie within TOL_MM of each other
// (transitively, into the lowest id, which keeps its position) and remaps faces; the merged-away
// vertices become unused. Grid hashing with cells of 16·tol, so a point needs its own cell plus
// the neighbours it is within tol of: about 1.4 lookups per point. Returns vertices merged.
std::uint64_t merge_vertices(Mesh& mesh, double tol_mm, std::span<const std::uint32_t> candidates);

// Vertices on an edge without exactly two faces, ascending.
std::vector<std::uint32_t> open_vertices(const Mesh& mesh, const EdgeTopology& topo);

// Turns each cap (a face of three distinct vertices, one lying inside its longest edge: within
// ON_EDGE_MM of it, or the face's area below kDegenerateAreaMm2; what a mesher leaves where it
// splits an edge for a T-junction) into two proper faces by flipping that edge with the face across
// it: faces A C M and C A D become A D M and D C M. Removing a cap instead leaves a hole of three
// collinear points whose only fill is the cap again, which then crosses its neighbours; a cap left
// in place crosses them too when its vertex was rounded off the edge (two_branches: OpenSCAD's
// union leaves caps 4 nm high along its seam, and 16 faces crossed). A cap that is not part of a
// closed surface (an edge without exactly one agreeing neighbour), or whose flip would make an edge
// that exists already or another degenerate face, is left for remove_degenerate_faces. Passes flip
// caps that share no face, each after one topology build. Returns caps flipped.
std::uint64_t flip_caps(Mesh& mesh, double on_edge_mm);

// Drops faces with a repeated vertex or an area below kDegenerateAreaMm2. Returns faces dropped.
std::uint64_t remove_degenerate_faces(Mesh& mesh);

// Drops repeated faces among those next to a boundary, non-manifold or misoriented edge (a
// duplicate always makes one of these). Same orientation: one copy stays; opposite orientations
// cancel in pairs. Returns faces dropped.
std::uint64_t remove_duplicate_faces(Mesh& mesh, const EdgeTopology& topo);

// Gives every vertex one fan: corners joined across two-face edges form a fan; each further fan of
// a vertex gets a copy of it. This separates faces meeting at non-manifold edges and vertices.
// Returns the vertex copies made.
std::uint64_t split_nonmanifold_vertices(Mesh& mesh, const EdgeTopology& topo);

// Orients faces consistently within each connected component by flipping the minority (so each
// component keeps its original majority orientation). COMPONENT receives a component id per face,
// numbered by lowest face. Error (kInfeasible) for a non-orientable component.
core::Result<std::uint64_t> orient_faces(Mesh& mesh, const EdgeTopology& topo, std::vector<std::uint32_t>& component);

struct HoleStats {
  std::uint64_t filled = 0;
  std::uint64_t faces_added = 0;
  std::uint64_t left_open = 0;
};

// Fills boundary loops of at most MAX_EDGES edges by minimum-area triangulation (Liepa 2003, the
// O(n^3) dynamic programme); new faces join their loop's component. A larger loop is an error
// (kInfeasible) unless ALLOW_OPEN.
core::Result<HoleStats> fill_holes(Mesh& mesh, const EdgeTopology& topo, std::vector<std::uint32_t>& component,
                                   std::uint32_t max_edges, bool allow_open);

// Groups faces by component into shells, classifies nesting with the generalised winding number,
// turns inside-out shells outwards (T3), keeps inward shells inside others as cavities and drops
// outward shells inside others (T8), and orders solids then cavities. Updates REPORT.
std::vector<Shell> build_shells(Mesh& mesh, const std::vector<std::uint32_t>& component, bool closed, RepairReport& report);

// Removes vertices no face uses, keeping order. Returns how many.
std::uint64_t remove_unused_vertices(Mesh& mesh);

}  // namespace polyaxis::mesh::detail
