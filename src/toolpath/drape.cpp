#include "drape.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "polyaxis/geom2d/clip.h"
#include "polyaxis/slicing/conformal.h"

namespace polyaxis::toolpath::detail {

namespace {

constexpr double kTwoPi = 2.0 * 3.14159265358979323846;

// The two rays of the warp either side of the direction at ANGLE (rad), and how far it lies from
// the first towards the second, in [0, 1).
struct RaysAbout {
  std::size_t first = 0, second = 0;
  double t = 0.0;
};

RaysAbout rays_about(double angle) {
  constexpr auto kRays = static_cast<std::size_t>(kWarpRays);
  double x = angle / kTwoPi * kWarpRays;
  x -= std::floor(x / kWarpRays) * kWarpRays;
  const auto j0 = static_cast<std::size_t>(x) % kRays;
  return {j0, (j0 + 1) % kRays, x - std::floor(x)};
}

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

SurfaceWarp::SurfaceWarp(const mesh::SurfaceDistance& base, const slicing::Layer& layer, double step_mm) : step_(step_mm) {
  const geom2d::Centroid c = geom2d::centroid(layer.polygons);
  cu_ = c.x, cv_ = c.y;
  const std::vector<double> reach = ray_reach(layer.polygons);
  const Vec3 d = layer.frame.d;
  length_.resize(static_cast<std::size_t>(kWarpRays));
  for (int j = 0; j < kWarpRays; ++j) {
    const auto samples = static_cast<std::size_t>(std::ceil(reach[static_cast<std::size_t>(j)] / step_)) + 2;
    length_[static_cast<std::size_t>(j)].assign(samples, 0.0);
    const double a = kTwoPi * j / kWarpRays, cu = std::cos(a), cv = std::sin(a);
    double height = NAN, along = 0.0;
    std::optional<mesh::Nearest> near;  // the sample before's: the distance queries start from it
    for (std::size_t i = 0; i < samples; ++i) {
      const double r = step_ * static_cast<double>(i);
      const Vec3 p = layer.frame.to_world(cu_ + r * cu, cv_ + r * cv);
      // Searched from the previous sample's height: a step or two of Newton.
      const double from = std::isnan(height) ? layer.height_mm : height;
      const auto l = slicing::lift(base, d, layer.conformal->level_mm, p, from - core::dot(p, d), &near);
      const double h = l ? core::dot(l->point, d) : height;
      if (i > 0) along += std::isnan(h) || std::isnan(height) ? step_ : std::hypot(step_, h - height);
      if (!std::isnan(h)) height = h;
      length_[static_cast<std::size_t>(j)][i] = along;
    }
  }
}

std::vector<double> SurfaceWarp::ray_reach(const std::vector<geom2d::Polygon>& polygons) const {
  // The farthest point of the section in each sector between two rays, from its edges walked at
  // half a step; both rays of a sector interpolate there.
  constexpr auto kRays = static_cast<std::size_t>(kWarpRays);
  std::vector<double> far(kRays, 0.0);
  for (const geom2d::Ring& ring : geom2d::rings_of(polygons)) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const double u0 = geom2d::to_mm(ring[i].x) - cu_, v0 = geom2d::to_mm(ring[i].y) - cv_;
      const double u1 = geom2d::to_mm(ring[(i + 1) % ring.size()].x) - cu_, v1 = geom2d::to_mm(ring[(i + 1) % ring.size()].y) - cv_;
      const int pieces = std::max(1, static_cast<int>(std::ceil(std::hypot(u1 - u0, v1 - v0) / (0.5 * step_))));
      for (int k = 0; k < pieces; ++k) {
        const double t = static_cast<double>(k) / pieces, u = u0 + (u1 - u0) * t, v = v0 + (v1 - v0) * t;
        const RaysAbout rays = rays_about(std::atan2(v, u));
        const double r = std::hypot(u, v);
        far[rays.first] = std::max(far[rays.first], r), far[rays.second] = std::max(far[rays.second], r);
      }
    }
  }
  // Between two samples an edge may cross a sector narrower than half a step (within
  // kWarpNarrowSteps steps of the centre) or swell by a quarter step: each ray reaches its
  // neighbours' farthest, kWarpMarginSteps steps more, and no less than that narrow disc.
  std::vector<double> reach(kRays);
  for (std::size_t j = 0; j < kRays; ++j) {
    const double widest = std::max({far[(j + kRays - 1) % kRays], far[j], far[(j + 1) % kRays]});
    reach[j] = std::max(widest + kWarpMarginSteps * step_, kWarpNarrowSteps * step_);
  }
  return reach;
}

double SurfaceWarp::radius_at(double r, double angle) const {
  const RaysAbout rays = rays_about(angle);
  auto along = [&](const std::vector<double>& l) {
    const double i = r / step_;
    const auto last = l.size() - 1;
    if (i >= static_cast<double>(last)) return l[last] + (r - step_ * static_cast<double>(last));
    const auto i0 = static_cast<std::size_t>(i);
    return l[i0] + (l[i0 + 1] - l[i0]) * (i - static_cast<double>(i0));
  };
  return along(length_[rays.first]) * (1.0 - rays.t) + along(length_[rays.second]) * rays.t;
}

std::array<double, 2> SurfaceWarp::forward(double u, double v) const {
  const double du = u - cu_, dv = v - cv_, r = std::hypot(du, dv);
  if (r == 0.0) return {u, v};
  const double k = radius_at(r, std::atan2(dv, du)) / r;
  return {cu_ + du * k, cv_ + dv * k};
}

std::array<double, 2> SurfaceWarp::inverse(double u, double v) const {
  const double du = u - cu_, dv = v - cv_, rho = std::hypot(du, dv);
  if (rho == 0.0) return {u, v};
  const double a = std::atan2(dv, du);
  // L grows at least as fast as r (an arc is no shorter than its chord's projection): r <= rho.
  double lo = 0.0, hi = rho;
  for (int it = 0; it < 60 && hi - lo > 1e-9; ++it) {
    const double mid = 0.5 * (lo + hi);
    (radius_at(mid, a) < rho ? lo : hi) = mid;
  }
  const double k = 0.5 * (lo + hi) / rho;
  return {cu_ + du * k, cv_ + dv * k};
}

std::vector<geom2d::Polygon> SurfaceWarp::warped(const std::vector<geom2d::Polygon>& polygons) const {
  std::vector<geom2d::Ring> rings;
  for (const geom2d::Ring& ring : geom2d::rings_of(polygons)) {
    geom2d::Ring out;
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const double u0 = geom2d::to_mm(ring[i].x), v0 = geom2d::to_mm(ring[i].y);
      const double u1 = geom2d::to_mm(ring[(i + 1) % ring.size()].x), v1 = geom2d::to_mm(ring[(i + 1) % ring.size()].y);
      const int pieces = std::max(1, static_cast<int>(std::ceil(std::hypot(u1 - u0, v1 - v0) / (0.5 * step_))));
      for (int k = 0; k < pieces; ++k) {
        const double t = static_cast<double>(k) / pieces;
        const auto w = forward(u0 + (u1 - u0) * t, v0 + (v1 - v0) * t);
        const geom2d::Point q{geom2d::to_units(w[0]), geom2d::to_units(w[1])};
        if (out.empty() || !(out.back() == q)) out.push_back(q);
      }
    }
    if (out.size() >= 3) rings.push_back(std::move(out));
  }
  return geom2d::union_rings(rings, geom2d::FillRule::kNonZero);
}

std::string drape(const mesh::SurfaceDistance& base, const slicing::Layer& layer, const SurfaceWarp& warp, double step_mm, LayerToolpaths& lt) {
  lt.deposit_length_mm = lt.travel_length_mm = 0.0;
  const slicing::Frame& f = layer.frame;
  auto unwarped = [&](Vec3 p) {
    const Vec3 rel = p - f.origin;
    const auto q = warp.inverse(core::dot(rel, f.u), core::dot(rel, f.v));
    return f.to_world(q[0], q[1]);
  };
  for (ThinRegion& thin : lt.thin) {
    thin.where_mm = unwarped(thin.where_mm);
    if (const auto l = slicing::lift(base, layer, thin.where_mm)) thin.where_mm = l->point;
  }
  for (Path& path : lt.paths) {
    path.points = densified(path.points, step_mm);
    std::vector<char> lifted(path.points.size(), 0);
    std::optional<mesh::Nearest> near;  // the point before's: the distance queries start from it
    for (std::size_t i = 0; i < path.points.size(); ++i) {
      PathPoint& p = path.points[i];
      p.position_mm = unwarped(p.position_mm);
      if (const auto l = slicing::lift(base, layer, p.position_mm, &near)) {
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
    std::vector<PathPoint> kept;
    kept.reserve(path.points.size());
    for (const PathPoint& p : path.points) {
      // A point's flag says whether the move into it deposits: the move into a point that falls
      // on the one before is empty, and the one before keeps its own (a path's first point,
      // reached with the process off, must not take its neighbour's and deposit on the way in).
      if (!kept.empty() && core::norm(p.position_mm - kept.back().position_mm) < kSamePointMm) continue;
      kept.push_back(p);
    }
    path.points = std::move(kept);
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
