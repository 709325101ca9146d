// Gap fill: one bead along the middle of a piece of a section too thin for a perimeter. Private to
// the toolpath module (toolpath.cpp).
#pragma once

#include <vector>

#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::toolpath::detail {

// The centre lines of PIECE, its outline simplified to within 0.01 mm first (more than 600 sides
// after that, or more than one hole, gives none):
// - without a hole, the longest path through the inner edges of its straight skeleton (CGAL);
// - with one hole (a thin tube's section), the loop of midpoints between each point of the outline
//   and the nearest point of the hole, closed (its last point is its first).
// Kept where the piece is at least MIN_WIDTH_MM wide (twice the skeleton's distance to the boundary
// there, cut where it crosses that width). A run's ends keep at least half of MIN_WIDTH_MM to the
// boundary, so the bead's round end (BEAD_MM / 2) passes the piece by no more than it does across
// it. Runs shorter than a quarter of a bead are dropped. Open polylines, (u, v) units. Side branches
// of the skeleton (into the corners of a wider piece) are not followed: what the line's bead does
// not cover stays a thin region for the caller to report.
std::vector<geom2d::Ring> centre_lines(const geom2d::Polygon& piece, double bead_mm, double min_width_mm);

// The parts of the open polylines LINES inside POLYGONS, without those shorter than a quarter of
// BEAD_MM (as centre_lines drops them).
std::vector<geom2d::Ring> lines_within(const std::vector<geom2d::Ring>& lines, const std::vector<geom2d::Polygon>& polygons, double bead_mm);

}  // namespace polyaxis::toolpath::detail
