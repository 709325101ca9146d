// Decomposition of a part into a tree of regions, each built support-free along its own
// direction (SPEC §2.3, Ruan et al. 2006 §4.1).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::analysis {

struct Region {
  std::uint32_t id = 0;
  std::optional<std::uint32_t> parent;  // none for the root
  Vec3 build_direction{0, 0, 1};        // the reverse of the base surface's outward normal
  Vec3 base_point;                      // a point of the base plane (the cut, or the plate)
  Vec3 base_normal{0, 0, 1};            // the base plane's normal, pointing into the region
  mesh::Mesh mesh;                      // closed, outward
  double volume_mm3 = 0.0;
  double unsupported_area_mm2 = 0.0;    // overhang area in its own direction (0 when support-free)
  bool support_free = false;
  std::string rule;  // how its base was found: "plate", "below the plate", "planar face", "fallback plane"
};

struct RegionTree {
  std::vector<Region> regions;  // parents before children; regions[0] is the root
};

struct DecomposeOptions {
  Vec3 root_direction{0, 0, 1};   // build direction of the root region (its base on the plate)
  double self_supporting_deg = 30.0;
  double face_normal_tolerance_deg = 10.0;  // Ruan: the splitting face's normal within 10° of the link
};

// Splits MESH at the break links of AXIS. For each break link, in order: the candidate splitting
// surfaces are the part's planar faces with a concave boundary edge whose normal is within the
// tolerance of the break link's direction or of the link before it (Ruan's father link), whose
// plane lies within the link's extent along that direction (Ruan Eq. 5), and, as the fallback, the
// plane through the link's start perpendicular to the break link. The region holding the link's end
// is cut by each candidate plane (capped); the piece holding the link's end becomes the child,
// built along the plane normal pointing into it; the candidate that leaves both pieces
// support-free (else the least unsupported area) is kept. Regions partition the part.
core::Result<RegionTree> decompose(const mesh::Mesh& mesh, const CentroidalAxis& axis, const DecomposeOptions& options = {});

}  // namespace polyaxis::analysis
