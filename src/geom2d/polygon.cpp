#include "polyaxis/geom2d/polygon.h"

#include <algorithm>
#include <cmath>

namespace polyaxis::geom2d {

std::int64_t to_units(double mm) { return std::llround(mm * kUnitsPerMm); }
double to_mm(std::int64_t units) { return static_cast<double>(units) / kUnitsPerMm; }

Int128 twice_signed_area(const Ring& ring) {
  Int128 sum = 0;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point& a = ring[i];
    const Point& b = ring[(i + 1) % n];
    sum += static_cast<Int128>(a.x) * b.y - static_cast<Int128>(b.x) * a.y;
  }
  return sum;
}

double signed_area_mm2(const Ring& ring) {
  return static_cast<double>(twice_signed_area(ring)) / (2.0 * kUnitsPerMm * kUnitsPerMm);
}

double area_mm2(const Polygon& polygon) {
  double a = signed_area_mm2(polygon.outer);
  for (const Ring& h : polygon.holes) a += signed_area_mm2(h);  // holes are clockwise: negative
  return a;
}

double area_mm2(const std::vector<Polygon>& polygons) {
  double a = 0.0;
  for (const Polygon& p : polygons) a += area_mm2(p);
  return a;
}

std::vector<Ring> rings_of(const std::vector<Polygon>& polygons) {
  std::vector<Ring> rings;
  for (const Polygon& p : polygons) {
    rings.push_back(p.outer);
    rings.insert(rings.end(), p.holes.begin(), p.holes.end());
  }
  return rings;
}

int orientation(Point a, Point b, Point c) {
  const Int128 d = static_cast<Int128>(b.x - a.x) * (c.y - a.y) - static_cast<Int128>(b.y - a.y) * (c.x - a.x);
  return d > 0 ? 1 : (d < 0 ? -1 : 0);
}

namespace {

bool on_segment(Point a, Point b, Point p) {  // p collinear with a-b: is it within the box?
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}

}  // namespace

bool segments_touch(Point a, Point b, Point c, Point d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4 && o1 * o2 <= 0 && o3 * o4 <= 0) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

bool is_simple(const Ring& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Point a = ring[i], b = ring[(i + 1) % n];
    if (a == b) return false;
    const Point c = ring[(i + 2) % n];
    // Adjacent edges overlap when they fold back on themselves.
    if (orientation(a, b, c) == 0 && n > 3 && on_segment(a, b, c) && !(c == a)) return false;
    if (orientation(a, b, c) == 0 && on_segment(b, c, a)) return false;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segments_touch(a, b, ring[j], ring[(j + 1) % n])) return false;
    }
  }
  return true;
}

namespace {

// Squared distance (units²) from P to the segment AB.
double distance2_to_segment(Point p, Point a, Point b) {
  const double ux = static_cast<double>(b.x - a.x), uy = static_cast<double>(b.y - a.y);
  const double px = static_cast<double>(p.x - a.x), py = static_cast<double>(p.y - a.y);
  const double l2 = ux * ux + uy * uy;
  const double t = l2 > 0.0 ? std::clamp((px * ux + py * uy) / l2, 0.0, 1.0) : 0.0;
  const double dx = px - t * ux, dy = py - t * uy;
  return dx * dx + dy * dy;
}

}  // namespace

Ring simplified(const Ring& ring, double tolerance_mm) {
  const std::size_t n = ring.size();
  if (n <= 3 || !(tolerance_mm > 0.0)) return ring;
  const double tol2 = std::pow(tolerance_mm * kUnitsPerMm, 2);
  // The point farthest from the first splits the ring into two chains.
  std::size_t far = 0;
  double far2 = -1.0;
  for (std::size_t i = 1; i < n; ++i) {
    const double dx = static_cast<double>(ring[i].x - ring[0].x), dy = static_cast<double>(ring[i].y - ring[0].y);
    if (dx * dx + dy * dy > far2) far2 = dx * dx + dy * dy, far = i;
  }
  std::vector<char> keep(n, 0);
  keep[0] = keep[far] = 1;
  // Chains [first, last] read cyclically (last may be n: the first point again).
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, far}, {far, n}};
  while (!stack.empty()) {
    const auto [first, last] = stack.back();
    stack.pop_back();
    if (last - first < 2) continue;
    const Point a = ring[first], b = ring[last % n];
    std::size_t worst = first;
    double worst2 = -1.0;
    for (std::size_t i = first + 1; i < last; ++i) {
      const double d2 = distance2_to_segment(ring[i], a, b);
      if (d2 > worst2) worst2 = d2, worst = i;
    }
    if (worst2 <= tol2) continue;
    keep[worst] = 1;
    stack.push_back({first, worst}), stack.push_back({worst, last});
  }
  Ring out;
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i]) out.push_back(ring[i]);
  }
  return out.size() < 3 ? ring : out;
}

Polygon simplified(const Polygon& polygon, double tolerance_mm) {
  Polygon out{simplified(polygon.outer, tolerance_mm), {}};
  out.holes.reserve(polygon.holes.size());
  for (const Ring& h : polygon.holes) out.holes.push_back(simplified(h, tolerance_mm));
  return out;
}

Centroid centroid(const std::vector<Polygon>& polygons) {
  double sx = 0.0, sy = 0.0, a2 = 0.0;
  for (const Ring& r : rings_of(polygons)) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double x0 = to_mm(r[i].x), y0 = to_mm(r[i].y);
      const double x1 = to_mm(r[(i + 1) % r.size()].x), y1 = to_mm(r[(i + 1) % r.size()].y);
      const double c = x0 * y1 - x1 * y0;
      a2 += c;
      sx += (x0 + x1) * c;
      sy += (y0 + y1) * c;
    }
  }
  Centroid out;
  out.area = a2 / 2.0;
  if (a2 != 0.0) {
    out.x = sx / (3.0 * a2);
    out.y = sy / (3.0 * a2);
  } else if (!polygons.empty() && !polygons.front().outer.empty()) {
    out.x = to_mm(polygons.front().outer.front().x);
    out.y = to_mm(polygons.front().outer.front().y);
  }
  return out;
}


}  // namespace polyaxis::geom2d
