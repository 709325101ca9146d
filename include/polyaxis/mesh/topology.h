// Edge adjacency of a triangle mesh: for every half-edge, its opposite half-edge when exactly two
// faces share the edge. Built by bucketing half-edges by their smaller vertex (a counting sort),
// in parallel parts over the faces, so the cost is linear in the number of faces and 12 bytes per
// half-edge + 4 per vertex and part.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

struct EdgeTopology {
  // opposite[h] for half-edge h = 3f+k: the other half-edge of the same undirected edge when the
  // edge has exactly two faces, else kNoHalfEdge (boundary or non-manifold edge).
  std::vector<std::uint32_t> opposite;
  std::uint64_t edges = 0;              // undirected edges
  std::uint64_t boundary_edges = 0;     // edges with one face
  std::uint64_t nonmanifold_edges = 0;  // edges with three or more faces
  std::uint64_t misoriented_edges = 0;  // two faces traversing the edge the same way

  bool closed() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};

// Preconditions: every index < mesh.vertices.size(), no face repeats a vertex.
EdgeTopology build_topology(const Mesh& mesh);

// Origin vertex of half-edge H and its destination.
inline std::uint32_t half_edge_from(const Mesh& mesh, std::uint32_t h) { return mesh.triangles[h / 3][h % 3]; }
inline std::uint32_t half_edge_to(const Mesh& mesh, std::uint32_t h) { return mesh.triangles[h / 3][(h % 3 + 1) % 3]; }

}  // namespace polyaxis::mesh
