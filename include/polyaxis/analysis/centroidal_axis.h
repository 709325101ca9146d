// Centroidal axis (Ruan et al. 2006, §3): centroids of cross-sections along the six major
// directions, linked into a graph of branches.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::analysis {

using core::Vec3;

struct AxisNode {
  std::uint32_t id = 0;
  Vec3 position;        // centroid of one outer loop of a section, mm
  Vec3 direction;       // the section direction (one of ±X, ±Y, ±Z) the centroid was found along
  double area_mm2 = 0;  // area of that loop's section (outer minus its holes)
  std::uint32_t branch = 0;  // the branch the node belongs to
};

struct AxisLink {
  std::uint32_t from = 0;  // node ids
  std::uint32_t to = 0;
  bool is_break = false;   // C¹ break: the link turns from the previous one by more than the break angle
};

struct AxisBranch {
  std::uint32_t id = 0;
  Vec3 direction;                         // major direction of the branch's sections
  std::optional<std::uint32_t> father;    // the branch it grew from (none for the root branch)
  std::vector<std::uint32_t> children;    // branches grown from it
  std::vector<std::uint32_t> brothers;    // other children of the same father
  std::vector<std::uint32_t> nodes;       // in growth order
};

struct CentroidalAxis {
  std::vector<AxisNode> nodes;
  std::vector<AxisLink> links;
  std::vector<AxisBranch> branches;
  double increment_mm = 0;  // `inc` used (Ruan: the smallest distance between two non-intersecting surfaces, clamped)
};

// The major direction (±X, ±Y, ±Z) nearest to D: where the centroidal axis of a part built along D
// starts (CentroidalAxisOptions::start_direction).
Vec3 nearest_major_direction(Vec3 d);

struct CentroidalAxisOptions {
  Vec3 start_direction{0, 0, 1};  // the root branch's major direction (the build direction)
  double min_increment_mm = 0.5;  // floor and ceiling of `inc`
  double max_increment_mm = 5.0;
  double break_angle_deg = 30.0;  // consecutive links turning more than this make a break link
};

// Precondition: MESH closed, manifold, outward (mesh::repair output); TOPOLOGY its adjacency.
core::Result<CentroidalAxis> centroidal_axis(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology,
                                             const CentroidalAxisOptions& options = {});

}  // namespace polyaxis::analysis
