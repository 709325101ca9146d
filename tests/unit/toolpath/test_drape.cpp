// The warp of a conformal layer (toolpath/drape.h): a point of the section goes to the radius that
// is the arc length over the layer's surface from the section's centroid along its ray. Checked on
// thin strips lying on spheres, sections whose reach differs a great deal from ray to ray (each
// ray is tabulated only as far as the section reaches about it): the arc length is measured here
// by lifting dense points of the ray onto the surface, and inverse undoes forward.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <utility>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/slicing/conformal.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/slicing/slice.h"
#include "support/meshes.h"
#include "support/repaired.h"
#include "toolpath/drape.h"

namespace polyaxis::toolpath {
namespace {

// The arc length over LAYER's surface from (u0, v0) to (u, v) along the straight line between them
// in the layer's plane, lifted at STEPS points.
double arc_length(const mesh::SurfaceDistance& base, const slicing::Layer& layer, double u0, double v0, double u, double v, int steps) {
  double length = 0.0;
  std::optional<Vec3> before;
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    const auto l = slicing::lift(base, layer, layer.frame.to_world(u0 + (u - u0) * t, v0 + (v - v0) * t));
    if (!l) return NAN;
    if (before) length += core::norm(l->point - *before);
    before = l->point;
  }
  return length;
}

struct Strip {
  double radius;          // of the sphere under it
  double length, width;   // of the strip, mm
  double turn_deg;        // the strip's heading about Z
};

TEST(SurfaceWarp, RadiiInAThinStripAreArcLengthsOverTheSurface) {
  for (const Strip s : {Strip{30, 44, 3, 0}, Strip{45, 60, 2.5, 37}, Strip{25, 36, 4, 101}}) {
    SCOPED_TRACE(s.radius);
    const Vec3 centre{0, 0, -s.radius};
    const auto base = std::make_shared<const mesh::SurfaceDistance>(test::repaired(test::shell_patch(centre, s.radius * 0.5, s.radius, 89, 192, 72)).mesh);
    // The layer 4 mm over the sphere whose section, seen along Z, is a strip turned about Z (a
    // prism standing on the sphere cut by the level: what slicing gives such a region).
    const double c = std::cos(s.turn_deg * M_PI / 180.0), sn = std::sin(s.turn_deg * M_PI / 180.0);
    slicing::Layer l;
    l.frame = slicing::plane_frame({0, 0, 1}, 4.0);
    l.height_mm = 4.0;
    l.conformal.emplace();
    l.conformal->level_mm = 4.0;
    auto in_plane = [&](double x, double y) {
      const Vec3 rel = Vec3{x * c - y * sn, x * sn + y * c, 0} - l.frame.origin;
      return std::array<double, 2>{core::dot(rel, l.frame.u), core::dot(rel, l.frame.v)};
    };
    geom2d::Ring ring;
    for (const auto& [x, y] : {std::pair{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}) {
      const auto q = in_plane(x * s.length, y * s.width);
      ring.push_back({geom2d::to_units(q[0]), geom2d::to_units(q[1])});
    }
    l.polygons = geom2d::union_rings({ring}, geom2d::FillRule::kNonZero);
    const slicing::Layer* layer = &l;
    const double step = 0.6;
    const detail::SurfaceWarp warp(*base, *layer, step);
    const geom2d::Centroid o2 = geom2d::centroid(layer->polygons);
    int checked = 0;
    // Points along the strip's axis and its sides, out to its ends (inside the section).
    for (double a = -0.47; a <= 0.47; a += 0.047) {
      for (double b : {-0.4, 0.0, 0.4}) {
        const auto [u, v] = in_plane(a * s.length, b * s.width);
        const auto w = warp.forward(u, v);
        const double measured = arc_length(*base, *layer, o2.x, o2.y, u, v, 400);
        ASSERT_TRUE(std::isfinite(measured));
        // Tabulated at steps of STEP and 128 rays, linear between: within a step's chord error.
        EXPECT_NEAR(std::hypot(w[0] - o2.x, w[1] - o2.y), measured, 0.01 + 0.002 * measured) << "at (" << u << ", " << v << ")";
        const auto back = warp.inverse(w[0], w[1]);
        EXPECT_NEAR(back[0], u, 1e-6);
        EXPECT_NEAR(back[1], v, 1e-6);
        ++checked;
      }
    }
    EXPECT_GT(checked, 40);
  }
}

}  // namespace
}  // namespace polyaxis::toolpath
