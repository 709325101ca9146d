// A layer: a planar section of a part with its plane, frame and thickness.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::slicing {

using core::Vec3;

// A right-handed orthonormal frame (u, v, d): d is the plane normal (build direction), u and v span
// the plane. Section polygons are in (u, v) coordinates relative to `origin`.
struct Frame {
  Vec3 origin;          // a point of the plane, mm
  Vec3 u{1, 0, 0};
  Vec3 v{0, 1, 0};
  Vec3 d{0, 0, 1};

  Vec3 to_world(double u_mm, double v_mm) const { return origin + u * u_mm + v * v_mm; }
};

// The frame of planes normal to DIRECTION (any non-zero vector; normalised here) at signed
// height HEIGHT_MM along it: origin = height·d; u is the world X axis projected onto the plane
// (the Y axis when d is within ~25° of X), v = d × u. For d = +Z this is the world frame.
Frame plane_frame(Vec3 direction, double height_mm);

// A conformal layer (conformal.h) is a curved surface: the level set at LEVEL_MM of the distance from
// a base surface. Its Layer keeps the section projected along d onto the frame's plane (the plane
// through the middle of the surface's span along d), so the planar machinery (offsets, fill,
// support) works on the projection; the toolpaths are then lifted onto the surface.
struct ConformalLayer {
  double level_mm = 0.0;              // the mid-surface's distance from the base
  double low_mm = 0.0, high_mm = 0.0; // the mid-surface's lowest and highest height along d (sampled)
  std::vector<std::vector<Vec3>> contours;  // the section's rings on the surface, world frame, closed implicitly
  std::vector<std::vector<Vec3>> axes;      // the distance's gradient (unit) at each point of contours
  // The section carried down the gradient onto the base (each contour point less level_mm along
  // its tool axis: the distance's gradient lines are straight and normal to the base), projected
  // along d, in the frame's (u, v): the slicer's overhang estimate compares footprints. (The
  // planner's support check carries each layer only onto the one below, with axes: footprints fold
  // where the base ends, at a rim whose gradient lines all start on its edge.)
  std::vector<geom2d::Polygon> footprint;
};

struct Layer {
  std::uint32_t index = 0;
  Frame frame;              // the section plane (the layer's mid-plane)
  double height_mm = 0.0;   // the plane's signed height along d
  double below_mm = 0.0;    // the layer spans [height - below, height + above] along d
  double above_mm = 0.0;
  std::vector<geom2d::Polygon> polygons;  // outer CCW, holes CW, strictly simple, canonical order
  double area_mm2 = 0.0;
  // Tilted layers (slice.h, SliceOptions::tilted): the plane is not parallel to the previous
  // layer's, so the thickness (the distance along d from this plane down to the previous layer's,
  // over the section) varies; these are its least and largest values over the section's corners,
  // and below/above hold half the thickness on the region's axis. Both 0 for a layer parallel to
  // the one below (the planar slicers): see thickness_range().
  double min_thickness_mm = 0.0, max_thickness_mm = 0.0;
  // Conformal layers only: the surface (height_mm is the middle of its span, below/above hold half
  // the thickness measured along the field's gradient, which is uniform).
  std::optional<ConformalLayer> conformal;

  double thickness_mm() const { return below_mm + above_mm; }
  // The least and largest thickness over the layer.
  std::pair<double, double> thickness_range() const {
    if (min_thickness_mm == 0.0 && max_thickness_mm == 0.0) return {thickness_mm(), thickness_mm()};
    return {min_thickness_mm, max_thickness_mm};
  }
};

}  // namespace polyaxis::slicing
