// Integer polygons: 2-D geometry on int64 coordinates at a fixed scale of 1 nm (STYLE.md
// "Numbers"), snapped once where 3-D becomes 2-D. Areas and orientations are exact (128-bit).
#pragma once

#include <cstdint>
#include <vector>

namespace polyaxis::geom2d {

// Integer units per millimetre: 1 unit = 1 nm. ±1e6 mm (core::kMaxCoordinateMm) is ±1e12 units,
// so a cross product of two differences stays below 2^127.
inline constexpr double kUnitsPerMm = 1e6;

// Exact products of coordinate differences (a GCC/Clang extension, hence __extension__).
__extension__ typedef __int128 Int128;

struct Point {
  std::int64_t x = 0;
  std::int64_t y = 0;
  friend bool operator==(const Point&, const Point&) = default;
};

using Ring = std::vector<Point>;  // closed implicitly: the last point connects to the first

// A polygon with holes: outer counter-clockwise, holes clockwise.
struct Polygon {
  Ring outer;
  std::vector<Ring> holes;
};

std::int64_t to_units(double mm);  // rounds to nearest; precondition |mm| <= 1e6
double to_mm(std::int64_t units);

// Twice the signed area of RING in units², exact. Positive for counter-clockwise.
Int128 twice_signed_area(const Ring& ring);
// Signed area in mm² (rounded from the exact value).
double signed_area_mm2(const Ring& ring);
// Area of a polygon (outer minus holes) in mm².
double area_mm2(const Polygon& polygon);
// Total area of POLYGONS in mm².
double area_mm2(const std::vector<Polygon>& polygons);
// Every ring of POLYGONS (outers and holes), for the ring-based booleans of clip.h.
std::vector<Ring> rings_of(const std::vector<Polygon>& polygons);

// Area-weighted centroid (mm) and signed area (mm²) of POLYGONS in their own (u, v) frame; for a
// zero area, the first outer ring's first point (or the origin when there is none).
struct Centroid {
  double x = 0.0, y = 0.0, area = 0.0;
};
Centroid centroid(const std::vector<Polygon>& polygons);

// Exact orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear.
int orientation(Point a, Point b, Point c);

// True when the closed segments AB and CD share a point (exact).
bool segments_touch(Point a, Point b, Point c, Point d);

// True when no two non-adjacent edges of RING touch or cross and no two adjacent edges overlap
// (exact predicates). O(n^2): meant for checks and tests.
bool is_simple(const Ring& ring);

// RING with the points dropped that Douglas–Peucker finds within TOLERANCE_MM of the chord
// between the points kept on either side (split at its first point and the point farthest from
// it): every dropped point stays within the tolerance of the ring returned. A ring that would keep
// fewer than three points is returned as it is. O(n log n) typical, O(n²) worst.
Ring simplified(const Ring& ring, double tolerance_mm);
// POLYGON with each of its rings simplified().
Polygon simplified(const Polygon& polygon, double tolerance_mm);

}  // namespace polyaxis::geom2d
