// Toolpaths of conformal layers (private to the toolpath module).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/slicing/layer.h"
#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::toolpath::detail {

// A map of a conformal layer's plane (its frame's (u, v), mm) onto a plane where distances along
// the rays from a centre (the section's centroid) are the curved surface's: the point at radius r
// along the ray at angle a goes to radius L(r, a), the arc length over the surface from the centre
// along that ray (tabulated on kWarpRays rays at steps of STEP_MM, linear between, each ray as far
// as the section reaches in the sectors either side of it; beyond that, or beyond the surface's
// reach, the ray runs on flat). Paths made on the warped section are spaced on the surface as on
// a plane along the rays (a slope of 55° no longer opens the spacing by 1/cos 55° = 1.74); across
// the rays a sphere's are closer by sin φ / φ (0.85 at 55°), a mild overlap. A blade's thin layer
// reaches far along two rays only: every ray tabulated as far as the farthest point, and on past
// the surface's edge where each lift fails after its last iteration, made the warps 56 % of the
// impeller's conformal plan.
class SurfaceWarp {
 public:
  SurfaceWarp(const mesh::SurfaceDistance& base, const slicing::Layer& layer, double step_mm);
  std::array<double, 2> forward(double u, double v) const;
  std::array<double, 2> inverse(double u, double v) const;  // forward's inverse (bisection along the ray)
  // POLYGONS (units) with every edge cut to half a step, mapped forward, and united (nonzero).
  std::vector<geom2d::Polygon> warped(const std::vector<geom2d::Polygon>& polygons) const;

 private:
  double radius_at(double r, double angle) const;  // L(r, angle)
  // How far each ray is tabulated, mm: the section's reach about it (POLYGONS, units).
  std::vector<double> ray_reach(const std::vector<geom2d::Polygon>& polygons) const;
  double cu_ = 0.0, cv_ = 0.0, step_ = 1.0;
  std::vector<std::vector<double>> length_;  // length_[ray][i]: L at r = i·step
};

// The rays of SurfaceWarp.
inline constexpr int kWarpRays = 128;
// How far past the section's farthest point near it a ray of SurfaceWarp is tabulated, in steps,
// and the disc round the centre every ray covers, in steps (there a sector is narrower than the
// half step the section's edges are walked at: 2π / kWarpRays · 10.2 steps = 0.5 step).
inline constexpr double kWarpMarginSteps = 2.0;
inline constexpr double kWarpNarrowSteps = 12.0;

// Consecutive path points nearer than this are one, mm: below the program's resolution (G-code
// words of 0.1 µm) such a point is no move of the tip, only a block whose rotary words differ in
// the last digit, the tool turning in place. Draped points that fall together, and the vertices a
// unit (1 nm) apart that the offsets' round joins leave (two_branches: 15 000), are merged.
inline constexpr double kSamePointMm = 1e-4;

// The paths of conformal LAYER, made on its section warped by WARP, carried onto its surface:
// every path is cut into pieces no longer than STEP_MM, each point is mapped back to the layer's
// plane, lifted along the layer's normal onto the level set (slicing::lift) and takes the
// distance's gradient as its tool axis. A travel point the surface cannot hold keeps the straight
// line between its lifted neighbours; consecutive points that land together are merged. The
// lengths of PATHS are recomputed. Returns a message naming the first deposit point that cannot be
// lifted, empty on success.
std::string drape(const mesh::SurfaceDistance& base, const slicing::Layer& layer, const SurfaceWarp& warp, double step_mm, LayerToolpaths& paths);

}  // namespace polyaxis::toolpath::detail
