// Direction-parallel (zigzag) fill of integer polygons by exact scanlines.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::toolpath::detail {

// Zigzag polylines filling PIECE (one connected polygon with holes, in 1 nm units), for lines
// along the direction ANGLE_RAD from the u axis, spread evenly across the piece: ceil(H / SPACING)
// lines for the piece's extent H across them, floor(H / lines) <= SPACING apart, the first and the
// last half that from the piece's lowest and highest points (none when H <= SPACING/2), so that
// beads SPACING wide leave no strip bare along either side. Neighbouring lines are joined, in boustrophedon order,
// along the piece's boundary between them when that boundary stays between the two lines;
// otherwise a new polyline starts. Each polyline has at least two points. Crossings are exact
// (integer arithmetic on the piece rotated once onto the scan direction, rounded to 1 nm).
// Precondition: SPACING > 0. Cost: O(n·lines_per_edge + k log k) for k crossings.
std::vector<geom2d::Ring> zigzag(const geom2d::Polygon& piece, double angle_rad, std::int64_t spacing);

}  // namespace polyaxis::toolpath::detail
