// analysis.json, written by `polyaxis analyze` (schema in docs/analyze.md).
#pragma once

#include <optional>
#include <string>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/analysis/decompose.h"
#include "polyaxis/analysis/overhang_map.h"
#include "polyaxis/analysis/skeleton.h"

namespace polyaxis::report {

struct AnalysisTimes {
  double overhang_s = 0, axis_s = 0, skeleton_s = 0, decompose_s = 0;
};

std::string analysis_json(const std::string& part, const analysis::OverhangMap& overhang, const analysis::CentroidalAxis& axis,
                          const std::optional<analysis::SkeletonGraph>& skeleton, const analysis::RegionTree& regions,
                          const AnalysisTimes& times);

}  // namespace polyaxis::report
