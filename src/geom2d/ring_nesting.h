// The union of rings that needs no boolean: simple rings that neither cross nor touch, nested with
// orientations alternating by depth, as the sections of a clean, consistently oriented mesh are.
// Their union is the rings themselves, sorted into polygons with holes; Clipper gives the same
// (clip.cpp hands it the rest). Private to geom2d.
#pragma once

#include <optional>
#include <vector>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::geom2d::detail {

// The union of RINGS (nonzero or even-odd: the same for them) when every ring has at least three
// points, no two consecutive ones equal and no three consecutive ones collinear; no two edges of
// any rings touch or cross but the adjacent ones at their common point; and every ring counts
// counter-clockwise at an even depth of nesting, clockwise at an odd one. Polygons as
// finish_polygons leaves them. Nullopt when any of that fails, or when telling it would take more
// than a few times the points' count of exact tests (many long edges in one place, thousands of
// rings in one another's boxes): the caller's boolean answers then.
std::optional<std::vector<Polygon>> union_of_nested_rings(const std::vector<Ring>& rings);

// Outer rings turned counter-clockwise and holes clockwise, each ring starting at its lowest point
// (least y, then x), holes and polygons sorted by their lowest points: the same set of polygons
// always comes out the same.
void finish_polygons(std::vector<Polygon>& polygons);

// union_rings through Clipper alone (clip.cpp), for the tests that compare the two.
std::vector<Polygon> union_rings_by_clipper(const std::vector<Ring>& rings, FillRule fill_rule);

}  // namespace polyaxis::geom2d::detail
