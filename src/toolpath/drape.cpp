#include "drape.h"

#include <fmt/format.h>

#include <cmath>

#include "polyaxis/slicing/conformal.h"

namespace polyaxis::toolpath::detail {

namespace {

// PATH's points with every move cut into pieces no longer than STEP_MM; a new point takes the
// deposit flag of the move it lies on.
std::vector<PathPoint> densified(const std::vector<PathPoint>& points, double step_mm) {
  std::vector<PathPoint> out;
  out.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) {
      const PathPoint &a = points[i - 1], &b = points[i];
      const double len = core::norm(b.position_mm - a.position_mm);
      const int pieces = static_cast<int>(std::ceil(len / step_mm));
      for (int j = 1; j < pieces; ++j) {
        const double t = static_cast<double>(j) / pieces;
        out.push_back({a.position_mm + (b.position_mm - a.position_mm) * t, b.tool_axis, b.deposit});
      }
    }
    out.push_back(points[i]);
  }
  return out;
}

}  // namespace

std::string drape(const mesh::SurfaceDistance& base, const slicing::Layer& layer, double step_mm, LayerToolpaths& lt) {
  lt.deposit_length_mm = lt.travel_length_mm = 0.0;
  for (Path& path : lt.paths) {
    path.points = densified(path.points, step_mm);
    std::vector<char> lifted(path.points.size(), 0);
    for (std::size_t i = 0; i < path.points.size(); ++i) {
      PathPoint& p = path.points[i];
      if (const auto l = slicing::lift(base, layer, p.position_mm)) {
        p.position_mm = l->point, p.tool_axis = l->axis, lifted[i] = 1;
      } else if (path.kind != PathKind::kTravel) {
        return fmt::format("conformal layer {}: the path point ({:.2f}, {:.2f}, {:.2f}) cannot be carried onto the layer's surface", layer.index,
                           p.position_mm.x, p.position_mm.y, p.position_mm.z);
      }
    }
    // Travel points off the surface: on the line between the nearest lifted points either side.
    for (std::size_t i = 0; i < path.points.size(); ++i) {
      if (lifted[i]) continue;
      std::size_t a = i, b = i;
      while (a > 0 && !lifted[a]) --a;
      while (b + 1 < path.points.size() && !lifted[b]) ++b;
      if (!lifted[a] || !lifted[b]) continue;  // nothing lifted at one end: keep the plane's point
      const double t = static_cast<double>(i - a) / static_cast<double>(b - a);
      path.points[i].position_mm = path.points[a].position_mm + (path.points[b].position_mm - path.points[a].position_mm) * t;
      path.points[i].tool_axis = core::normalized(path.points[a].tool_axis * (1.0 - t) + path.points[b].tool_axis * t);
    }
    for (std::size_t i = 1; i < path.points.size(); ++i) {
      const double len = core::norm(path.points[i].position_mm - path.points[i - 1].position_mm);
      if (path.kind == PathKind::kTravel) {
        lt.travel_length_mm += len;
      } else if (path.points[i].deposit) {
        lt.deposit_length_mm += len;
      }
    }
  }
  return {};
}

}  // namespace polyaxis::toolpath::detail
