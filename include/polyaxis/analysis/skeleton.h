// Distance-field skeleton (Dwivedi & Kovacevic 2006, §2.1; SPEC §2.2): the signed distance field of
// the solid on a regular grid, its ridge voxels (the morphological skeleton), a 1-voxel-wide curve
// skeleton centred on those ridges, and the graph of that curve with one skeleton vector per edge.
// A second analysis beside the centroidal axis (centroidal_axis.h).
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::analysis {

using core::Vec3;

struct DistanceFieldOptions {
  double voxel_mm = 0.0;                 // edge of a cubic voxel; 0: largest bounding-box extent / 64
  std::uint64_t max_cells = 2'000'000;   // the voxel grows (never shrinks) until the grid has at most this many cells
  int threads = 0;                       // worker threads for the grid passes; 0: all. Output is the same at any count
};

// Signed distance F on voxel centres origin + (i + ½, j + ½, k + ½)·voxel_mm. Dwivedi Eq. 1 with
// F > 0 inside (so F is the radius of the largest inscribed ball there) and F < 0 outside; the
// printed Eq. 1 carries a minus sign on both branches. The grid has a margin of two outside voxels
// around the part's bounding box.
struct DistanceField {
  Vec3 origin;                 // corner of voxel (0, 0, 0), mm
  double voxel_mm = 0.0;
  std::uint32_t nx = 0, ny = 0, nz = 0;
  std::vector<float> values;   // mm, index i + nx·(j + ny·k)
  std::uint64_t inside_cells = 0;

  std::size_t index(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return i + static_cast<std::size_t>(nx) * (j + static_cast<std::size_t>(ny) * k);
  }
  Vec3 centre(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return origin + Vec3{i + 0.5, j + 0.5, k + 0.5} * voxel_mm;
  }
  // F at the voxel containing P (clamped to the grid), mm.
  double at(Vec3 p) const;
};

// Inside/outside: the winding number of the surface about each voxel centre, counted along +X rows
// from exact-rule ray crossings (a facet is crossed when the row's (y, z) lies in its projection; a
// row through a projected edge or vertex is settled by symbolic perturbation of the row to
// (y + ε, z + ε²), each edge evaluated in one canonical vertex order, so a closed surface is crossed
// exactly once where it should be). A centre is inside when the winding number is at least 1
// (core::kInsideWindingNumber), so cavities and overlapping shells are handled; a centre exactly on
// a crossing counts the crossing as behind it.
// Distance: the exact Euclidean distance transform of the voxel set (Felzenszwalb & Huttenlocher
// 2012, three separable 1-D lower-envelope passes) to the nearest voxel of the other class, minus
// half a voxel: it approximates the distance to the surface to within about half a voxel for a
// surface resolved by the grid (a feature thinner than a voxel may vanish).
// Preconditions: MESH closed and outward (mesh::repair output). Errors: no faces or an empty,
// flat or non-finite bounding box (kInvalidInput); no voxel centre inside the part, i.e. the part is
// thinner than the grid resolves (kInfeasible). Cost O(cells + row crossings); memory about 13 bytes
// per cell while it runs, 4 in the result.
core::Result<DistanceField> signed_distance_field(const mesh::Mesh& mesh, const DistanceFieldOptions& options = {});

enum class SkeletonNodeKind : std::uint8_t {
  kEnd,       // one edge
  kBranch,    // three or more edges
  kCorner,    // two edges: the skeleton turns there by more than SkeletonOptions::corner_angle_rad
  kIsolated,  // no edge: the whole component thinned to one blob (a ball, a cube)
  kLoop,      // two edges or one closed edge: a chosen point on a skeleton cycle without branches
};

struct SkeletonNode {
  std::uint32_t id = 0;
  Vec3 position;            // mm: mean of the node's voxel centres
  double radius_mm = 0.0;   // F there (largest value over the node's voxels)
  std::uint32_t degree = 0; // edge ends at the node (a closed edge counts twice)
  SkeletonNodeKind kind = SkeletonNodeKind::kEnd;
};

struct SkeletonEdge {
  std::uint32_t from = 0;      // node ids; `from` is the end nearer the root (see SkeletonGraph)
  std::uint32_t to = 0;
  std::vector<Vec3> polyline;  // from's position, the chain's voxel centres, to's position (mm)
  double length_mm = 0.0;      // of the polyline
  Vec3 direction;              // skeleton vector: unit (to − from); zero for a closed edge
};

struct SkeletonGraph {
  std::vector<SkeletonNode> nodes;
  std::vector<SkeletonEdge> edges;
  // One per connected component: its lowest node along SkeletonOptions::build_direction among the
  // nodes at least half as thick (radius) as its thickest node (ties: lower id), i.e. on the body
  // rather than at a thin fin's tip. Edges are oriented breadth-first away from it, so skeleton
  // vectors point away from the build plate and from the body. Ascending.
  std::vector<std::uint32_t> roots;
  double voxel_mm = 0.0;
  std::uint64_t inside_voxels = 0;
  std::uint64_t ridge_voxels = 0;     // the morphological skeleton before thinning
  std::uint64_t skeleton_voxels = 0;  // the thinned curve set
  std::uint32_t pruned_spurs = 0;
};

struct SkeletonOptions {
  DistanceFieldOptions field;           // grid of the distance field
  // Gagvani & Silver's thinness parameter, in voxels: a voxel is a ridge voxel when F exceeds the
  // mean of its 26 neighbours by more than this (a one-voxel ridge of a slab exceeds it by 9/26).
  double ridge_threshold_vox = 0.2;
  // A spur (edge from branch node j to end node e) is removed when the end's inscribed ball reaches
  // less than max(2 voxels, spur_factor · r_j) beyond j's: |p_e − p_j| + r_e − r_j. A spur into a
  // cube's corner reaches (√3 − 1)·r_j ≈ 0.73 r_j, into an edge (√2 − 1)·r_j; a limb about its length.
  double spur_factor = 0.75;
  // Chains are split into separate edges where their simplified polyline turns by more than this,
  // so each edge carries one skeleton vector (an L gives a column edge and an arm edge).
  double corner_angle_rad = 0.6108652381980153;  // 35°
  Vec3 build_direction{0, 0, 1};        // roots are the lowest nodes along this (unit or not)
};

// The distance-field skeleton of MESH (Dwivedi & Kovacevic §2.1; the thinning and graph steps are
// ours, see skeleton.cpp). Preconditions and errors as signed_distance_field. Deterministic: the same graph at any thread
// count. Cost: the field, plus O(max radius in voxels × surface voxels) simple-point tests.
core::Result<SkeletonGraph> skeleton(const mesh::Mesh& mesh, const SkeletonOptions& options = {});

}  // namespace polyaxis::analysis
