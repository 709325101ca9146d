// Polygon booleans and offsets on integer polygons, through Clipper (polyclipping 6.4); a union
// that needs no boolean (the sections of a clean mesh) is made without it, the same polygons
// point for point (src/geom2d/ring_nesting.h).
#pragma once

#include <vector>

#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::geom2d {

enum class FillRule { kEvenOdd, kNonZero };

// Union of RINGS under FILL_RULE, nested into polygons with holes (outer CCW, holes CW), in a
// deterministic order (by outer ring's lowest point). Self-intersecting input is resolved by the
// fill rule (RELIABILITY T6 uses kNonZero).
std::vector<Polygon> union_rings(const std::vector<Ring>& rings, FillRule fill_rule);

// The boundary of the union of RINGS under FILL_RULE (outer rings CCW, holes CW), not nested into
// polygons: for what needs only the area covered (an offset, a boolean). Nesting Clipper's result
// (its PolyTree) is quadratic in the rings where many meet along edges, as the sections of
// neighbouring regions do.
std::vector<Ring> union_boundary(const std::vector<Ring>& rings, FillRule fill_rule);

// Symmetric difference and difference of two sets of rings, each read under the nonzero rule.
std::vector<Polygon> xor_rings(const std::vector<Ring>& a, const std::vector<Ring>& b);
std::vector<Polygon> difference_rings(const std::vector<Ring>& a, const std::vector<Ring>& b);
std::vector<Polygon> intersection_rings(const std::vector<Ring>& a, const std::vector<Ring>& b);

// Offsets POLYGONS by DELTA_MM (negative shrinks) with mitred corners limited to 2·|delta|.
std::vector<Polygon> offset(const std::vector<Polygon>& polygons, double delta_mm);
// The same for the area RINGS bound (outer rings CCW, holes CW; overlapping rings add up).
std::vector<Polygon> offset_rings(const std::vector<Ring>& rings, double delta_mm);

// The area a disc of RADIUS_MM covers swept along each open polyline of PATHS (round joins and
// ends): the footprint of beads laid along them. Polylines of one point give a disc.
std::vector<Polygon> sweep_open(const std::vector<Ring>& paths, double radius_mm);

// The parts of the open polylines PATHS inside RINGS (nonzero rule), as open polylines.
std::vector<Ring> clip_open(const std::vector<Ring>& paths, const std::vector<Ring>& rings);

}  // namespace polyaxis::geom2d
