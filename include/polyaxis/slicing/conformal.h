// Conformal layers (Kapil et al., offset surfaces of a prebuilt feature; SPEC §2.4): the layers are
// level sets of the distance from a base surface, and the tool axis follows the distance's
// gradient. slice() makes them when SliceOptions::conformal_base is set:
//
// - the region's mesh is refined (refined_for_levels) so the distance, sampled at its corners and
//   linear over each face, follows the curved levels; a layer's section is the level set on the refined
//   mesh (SectionContext with a field), projected along d onto the plane normal to d;
// - the levels run from the base (or the region's nearest point to it, when it does not touch it)
//   to the farthest point in n equal steps, n the count whose step is nearest the process's layer
//   inside [min, max]. The distance's gradient has length 1, so the thickness measured along the
//   tool axis (the gradient) is that step at every point;
// - each layer's surface must be a height field over the plane along d (the gradient at least
//   kMinRise along d) where the section lies; where it folds over, slicing fails with kInfeasible.
//   Its contour rings and a grid of interior points are lifted onto the surface to find its span,
//   and its area (Layer::area_mm2) is the projected area times the mean of 1/(g·d) over the grid:
//   the area on the surface, so Σ area × thickness estimates the deposited volume.
#pragma once

#include <cstddef>
#include <optional>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/slicing/layer.h"

namespace polyaxis::slicing {

// The least component along d of the distance's gradient over a conformal layer (cos 84°).
inline constexpr double kMinRise = 0.1;
// The region is refined where the distance, linear over an edge, misses its value at the edge's
// middle by more than this (mm)...
inline constexpr double kFieldToleranceMm = 0.02;
// ... and refused (kInfeasible) when that takes more faces than this.
inline constexpr std::size_t kMaxRefinedFaces = 2'000'000;

// MESH refined for BASE's levels: every edge longer than MIN_EDGE_MM whose middle's distance from
// BASE differs from the mean of its ends' by more than kFieldToleranceMm is bisected
// (mesh::refine), so the levels, linear over each face, follow the distance. Nullopt beyond
// kMaxRefinedFaces.
std::optional<mesh::Mesh> refined_for_levels(const mesh::Mesh& mesh, const mesh::SurfaceDistance& base, double min_edge_mm);

struct Lifted {
  Vec3 point;  // on the level set, world frame
  Vec3 axis;   // the distance's gradient there, unit, away from the base: the tool axis
};

// The point of the level set LEVEL_MM of BASE's signed distance on the line through P along the unit
// vector D, searched from P + D·S0_MM (safeguarded Newton: the distance is 1-Lipschitz, so a step
// of r/rise with rise <= 1 never falls short, and a bracket catches overshoots). Nullopt where the
// line does not meet the level within reach or meets it where the gradient rises less than kMinRise
// along D (the level is no height field over the plane normal to D there).
// NEAR, when given, holds the answer of BASE's last distance query near P (a lift of the point
// before along a path or a ray): the queries start from it (mesh::SurfaceDistance::nearest), and it
// is left holding this lift's last.
std::optional<Lifted> lift(const mesh::SurfaceDistance& base, Vec3 d, double level_mm, Vec3 p, double s0_mm = 0.0,
                           std::optional<mesh::Nearest>* near = nullptr);

// The same for a conformal layer (Layer::conformal set): P is any point, lifted along the layer's
// frame normal onto its mid-surface, searched from the layer's height.
std::optional<Lifted> lift(const mesh::SurfaceDistance& base, const Layer& layer, Vec3 p, std::optional<mesh::Nearest>* near = nullptr);

}  // namespace polyaxis::slicing
