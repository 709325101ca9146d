// Moving the tool between regions built along different directions without crossing the part:
// out along the tool axis to a sphere around the part, over the sphere with the nozzle pointing
// away from its centre while the axis turns, and in along the new axis.
#pragma once

#include <vector>

#include "polyaxis/core/vec3.h"

namespace polyaxis::planner {

using core::Vec3;

// Largest turn of the tool axis, and largest step along the sphere, between two transit points
// (degrees). The chord between two such points dips below the sphere by R·(1 − cos 2.5°) < R/1000.
inline constexpr double kTransitStepDeg = 5.0;

struct TransitPoint {
  Vec3 tip;
  Vec3 axis;  // unit
};

// The points from FROM (tool axis A) to TO (tool axis B), both inside the sphere (CENTRE, RADIUS)
// that holds the whole part with room for the nozzle, neither end included:
//  1. out along A to where that ray leaves the sphere (QA);
//  2. along the sphere from QA to the pole CENTRE + RADIUS·A, axis A (every point of that arc has
//     (X − CENTRE)·A >= 0, so the ray from it along A stays outside the sphere);
//  3. along the great circle from that pole to the pole of B, the axis the outward radius (a
//     reversal, B = −A, goes through a pole perpendicular to A, the one nearest to the XY plane
//     when A is vertical); where that circle would go lower than both poles (two axes below the
//     horizon at distant azimuths), with their latitude and azimuth interpolated evenly instead,
//     which stays between the poles' latitudes;
//  4. along the sphere to QB (where the ray from TO along B leaves it), axis B; then TO is
//     approached along −B.
// Steps are at most kTransitStepDeg. A and B need not be unit.
std::vector<TransitPoint> transit(Vec3 from, Vec3 a, Vec3 to, Vec3 b, Vec3 centre, double radius);

// Where the ray P + s·D (s >= 0, D unit) leaves the sphere (CENTRE, RADIUS); P itself when it is
// already outside.
Vec3 ray_exit(Vec3 p, Vec3 d, Vec3 centre, double radius);

}  // namespace polyaxis::planner
