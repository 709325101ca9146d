// Planar slicing along any direction: uniform or adaptive layer thickness.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/slicing/layer.h"

namespace polyaxis::slicing {

// Limits for adaptive thickness; each is off when unset. A layer takes the largest thickness in
// [min_mm, max_mm] (on the snap grid, if any) for which every limit set holds between its bottom
// and top sections; when none does, it takes min_mm and is counted in `limit_violations`. The
// range wins over the limits at a top that narrows: a remainder thinner than min_mm joins the last
// layer (or the last two share it) even where that breaks a limit, counted in `limit_violations`
// too; a top that still overhangs keeps its thin layer.
struct AdaptiveLimits {
  std::optional<double> cusp_mm;          // staircase height t·|n·d| over the non-flat facets in the layer
  std::optional<double> voldiff;          // Ruan Eq. 9, see adaptive.cpp for the normalisation
  std::optional<double> area_deviation;   // Hayasi: |A_top − A_bottom| / A_bottom
  std::optional<double> overhang_deg;     // Kapil Fig. 4: top within bottom grown by t·tan(α)
  // With overhang_deg: the top may also step out by up to this much (mm) whatever t is, the step a
  // tilted torch may take over the layer below (planner/support.h): grown by max(t·tan α, step).
  std::optional<double> overhang_step_mm;
};

struct SliceOptions {
  Vec3 direction{0, 0, 1};   // build direction, any non-zero vector
  double layer_mm = 0.2;     // uniform thickness (ignored when adaptive)
  bool adaptive = false;
  AdaptiveLimits limits;
  double min_mm = 0.1;       // adaptive range
  double max_mm = 1.0;
  // Adaptive thicknesses are multiples of this (a machine's Z resolution), when > 0 ...
  double snap_mm = 0.0;
  // ... or one of these (a stock of sheet thicknesses), when not empty. Overrides snap_mm.
  std::vector<double> thickness_stock_mm;
  int threads = 0;           // 0: all cores (oneTBB); the output does not depend on it
  // Tilted "3-D" layers (Ruan §4.2.2, tilted.cpp) instead of parallel planes: the first layer
  // normal to DIRECTION, then each plane along the centroidal axis of the sections, thickness in
  // [min_mm, max_mm] at every corner of its section, under limits.voldiff and limits.overhang_deg
  // (the other limits, snap_mm and the stock are for parallel layers and are not used).
  bool tilted = false;
  // Tilted layers: refuse (kInfeasible) as soon as the layers that give up a limit leave more than
  // this overhang (mm², as overhang_estimate_mm2 counts it): a caller comparing with planar layers
  // stops once tilted ones can no longer win.
  std::optional<double> give_up_overhang_mm2;
  // Conformal layers (conformal.h) when set: level sets of the distance from this surface, a
  // thickness in [min_mm, max_mm] as near layer_mm as divides the part's farthest distance evenly,
  // the sections projected along DIRECTION. The mesh is refined first where the distance is not
  // linear over its edges, down to edges of conformal_edge_mm (conformal.h refined_for_levels).
  std::shared_ptr<const mesh::SurfaceDistance> conformal_base;
  double conformal_edge_mm = 1.0;
};

struct SliceResult {
  std::vector<Layer> layers;
  std::uint32_t open_chains = 0;       // loops that did not close (only on an open mesh)
  std::uint32_t limit_violations = 0;  // adaptive layers where no thickness met every limit
  double total_area_mm2 = 0.0;
  double volume_estimate_mm3 = 0.0;    // Σ area × thickness
  // Conformal layers: the base surface their levels are measured from (toolpaths are lifted onto
  // them through it, conformal.h lift()); null for planar and tilted layers.
  std::shared_ptr<const mesh::SurfaceDistance> conformal_base;
};

// The strategies a region's layers can take (SliceOptions::tilted, SliceOptions::conformal_base).
enum class LayerStrategy { kPlanar, kTilted, kConformal };
const char* layer_strategy_name(LayerStrategy s);

// The area of every layer beyond the layer below it (projected along the layer's normal when the
// two are not parallel) grown by max(t·tan ALPHA_DEG, STEP_MM), t the layer's least thickness,
// summed over the layers after the first (mm²): the overhang a planner's support check would find
// with the torch stepping out at most STEP_MM (planner/support.h). Cost: one offset and one
// difference a layer.
double overhang_estimate_mm2(const SliceResult& slices, double alpha_deg, double step_mm);

// Checks OPTIONS (kUsage naming the option): finite non-zero direction, positive thicknesses,
// min <= max, positive limits.
core::Status validate(const SliceOptions& options);

// Slices MESH (closed, manifold, outward: mesh::repair output). Uniform layers of thickness t
// start at the mesh's lowest point along d; layer k's plane is at min + (k + ½)·t, so
// Σ area × t is the midpoint rule for the volume. Layers are cut in parallel; the result is the
// same at any thread count. TOPOLOGY: the mesh's edge adjacency if the caller has it
// (RepairedMesh::topology), else it is built. Cost: O(F + crossings + layers).
core::Result<SliceResult> slice(const mesh::Mesh& mesh, const SliceOptions& options, const mesh::EdgeTopology* topology = nullptr);

}  // namespace polyaxis::slicing
