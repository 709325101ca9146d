// One thick layer's sloped edge (lamination.h): the reference contour's samples, their profiles
// through the layer and the jet cuts that follow them.
#pragma once

#include <vector>

#include "polyaxis/lamination/lamination.h"
#include "polyaxis/mesh/distance.h"
#include "sections.h"

namespace polyaxis::lamination::detail {

// Largest curvature of a profile (mm off the chord of its neighbours) still read as straight.
inline constexpr double kProfileTolMm = 2e-3;
// The profile's lowest and highest heights stand this far inside the layer (a plane through a
// flat face belongs to the material above it: section.h's tie rule).
inline constexpr double kFaceInsetMm = 1e-4;

struct EdgeContext {
  const SectionStack& stack;
  const mesh::SurfaceDistance& surface;  // the part, for the facet normal under a profile point
  const LaminateOptions& options;
};

// How far from P along N the ray first meets LOOP's ring of samples again (beyond MIN_MM), or
// infinity: a hole's width there, for its cuts and its lead-in.
double distance_across(const EdgeLoop& loop, Vec2 p, Vec2 n, double min_mm);

// The edge model of the layer [Z0, Z0 + T]: pieces from the section at its middle, each sample's
// profile at the sub-slices and the cuts. Layer::area_deviation and the deviation volumes are not
// filled here (deviation.cpp).
Layer build_layer(const EdgeContext& context, double z0, double t);

}  // namespace polyaxis::lamination::detail
