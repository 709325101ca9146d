// `polyaxis analyze` as a library call: the overhang map, the centroidal axis, the skeleton and the
// region tree of a repaired part, with the JSON the CLI writes (analysis.json) and the report of
// `polyaxis inspect`.
#pragma once

#include <optional>
#include <string>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/analysis/decompose.h"
#include "polyaxis/analysis/overhang_map.h"
#include "polyaxis/analysis/skeleton.h"
#include "polyaxis/core/result.h"
#include "polyaxis/core/tolerances.h"
#include "polyaxis/mesh/load_part.h"
#include "polyaxis/report/analysis_json.h"

namespace polyaxis::report {

struct AnalyzeOptions {
  analysis::RootBase root_base;                                  // analysis::parse_root_base
  bool skeleton = true;                                          // the distance-field skeleton (the slowest stage)
  double voxel_mm = 0.0;                                         // its grid step; 0: the part's size / 64
  double self_supporting_deg = core::kDefaultSelfSupportingDeg;  // from vertical, degrees, in [0, 89]
  double break_angle_deg = 30.0;                                 // centroidal-axis links turning more are break links, in [1, 179]
};

struct PartAnalysis {
  core::Vec3 root_direction;  // the root region's build direction
  analysis::OverhangMap overhang;
  analysis::CentroidalAxis axis;
  std::optional<analysis::SkeletonGraph> skeleton;
  analysis::RegionTree tree;
  AnalysisTimes times;
};

// The analysis of PART. Errors: kUsage for options out of range, and those of the stages
// (analysis::root_direction, centroidal_axis, skeleton, decompose).
core::Result<PartAnalysis> analyze_part(const mesh::RepairedMesh& part, const AnalyzeOptions& options = {});

// PART's volume and surface as a solid: the sums over its shells (cavities subtract), or, where
// separate bodies overlap (faces crossing, found by repair's self-intersection check), those of
// their union (mesh::unite_overlapping_shells), which UNITED then says.
struct SolidMeasure {
  double volume_mm3 = 0.0, area_mm2 = 0.0;
  bool united = false;
};
SolidMeasure solid_measure(const mesh::RepairedMesh& part);

// `polyaxis inspect --json` for PART read from PATH (docs/inspect.md): sizes, shells, repairs and
// the overhang along +Z at SELF_SUPPORTING_DEG (from vertical, degrees). CHECKED: whether the
// self-intersection check ran.
std::string inspect_json(const mesh::LoadedPart& part, const std::string& path, double self_supporting_deg, bool checked);

}  // namespace polyaxis::report
