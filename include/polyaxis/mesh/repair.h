// Turning a raw triangle soup into a closed, manifold, outward-oriented mesh, reporting every
// change (RELIABILITY.md rows F7, F8, T1–T9).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/core/tolerances.h"
#include "polyaxis/io/raw_mesh.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::mesh {

struct RepairOptions {
  double merge_mm = core::kVertexMergeMm;  // vertices closer than this merge (T9); capped at 1e-5 × diagonal
  std::uint32_t max_hole_edges = core::kDefaultMaxHoleEdges;  // larger holes are refused (T1)
  bool allow_open = false;             // keep larger holes open instead of refusing the part
  bool strict = false;                 // self-intersections are refused (T6) instead of warned
  bool check_self_intersections = true;  // CGAL pass, the slowest part of repair
};

// What repair did. Every count is zero on a clean closed mesh.
struct RepairReport {
  std::uint64_t merged_vertices = 0;         // T9: vertices of open edges merged into a neighbour within merge_mm
  std::uint64_t unused_vertices = 0;         // vertices no face referenced
  std::uint64_t flipped_caps = 0;            // T5: zero-area faces with a vertex inside an edge, flipped away
  std::uint64_t degenerate_faces = 0;        // T5: repeated vertex or zero area, removed
  std::uint64_t duplicate_faces = 0;         // T4: same three vertices as another face, removed
  std::uint64_t nonmanifold_edges = 0;       // T2: edges with three or more faces, before splitting
  std::uint64_t split_vertices = 0;          // T2: vertex copies made to separate fans
  std::uint64_t flipped_faces = 0;           // T3: faces flipped to agree with their neighbours
  std::uint64_t inverted_shells = 0;         // T3: inside-out shells turned outwards
  std::uint64_t holes_filled = 0;            // T1
  std::uint64_t hole_faces_added = 0;
  std::uint64_t open_holes = 0;              // holes left open under allow_open
  std::uint64_t interior_shells_removed = 0; // T8: same-orientation shells inside another (union)
  std::uint64_t self_intersecting_faces = 0; // T6: faces that cross another face

  // One human-readable line per non-zero count, in a fixed order.
  std::vector<std::string> lines() const;
};

struct RepairedMesh {
  Mesh mesh;                  // faces grouped by shell
  std::vector<Shell> shells;  // solids first (by descending volume), then cavities
  RepairReport report;
  std::vector<std::uint32_t> self_intersecting;  // face indices in `mesh`, sorted
  std::vector<std::string> warnings;              // unit suspicions (F8) and the like
  EdgeTopology topology;      // edge adjacency of `mesh`, for the stages after repair
  bool watertight = false;  // every edge has exactly two faces
  bool manifold = false;    // every edge has at most two faces and every vertex one fan
};

// Repairs RAW. Errors: coordinates out of range (F7, kInfeasible); nothing left after removing
// degenerate faces (kInvalidInput); a hole larger than max_hole_edges without allow_open, a
// non-orientable shell, an unresolved non-manifold edge, self-intersections under strict
// (kInfeasible). Deterministic. Cost: O(n) for the topology passes plus the self-intersection
// check (box intersection, O(n log n) typical).
core::Result<RepairedMesh> repair(io::RawMesh raw, const RepairOptions& options = {});

// PART's solid shells united into one solid (CGAL corefinement) and repaired again, with its
// self-intersecting faces listed: for a part of separate bodies that overlap, put together without
// a union as many exports leave them. None when PART has fewer than two shells, a cavity or an
// open shell, when a body crosses itself, or when CGAL cannot unite them. Cost: O(F log F) a shell.
std::optional<RepairedMesh> unite_overlapping_shells(const RepairedMesh& part);

}  // namespace polyaxis::mesh
