// Sections of a part along +Z at any height, and 2-D ray queries on one section: what the sloped
// edge model of lamination.h is measured from.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/lamination/lamination.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::lamination::detail {

// Faces bucketed by height so that a section at any height reads only the faces that may cross it.
class SectionStack {
 public:
  explicit SectionStack(const mesh::Mesh& mesh);
  // The part's section at H (nonzero union, outer CCW, holes CW), thread-safe.
  std::vector<geom2d::Polygon> at(double h) const;
  double min_z() const { return context_.min_height(); }
  double max_z() const { return context_.max_height(); }

 private:
  slicing::SectionContext context_;
  double bin_mm_ = 1.0;
  std::vector<std::vector<std::uint32_t>> bins_;  // faces whose height range meets each bin
};

// The boundary segments of one section in mm, in a uniform grid, for rays from points of another
// section. Every segment runs with the material on its left (section.h), so its right-hand normal
// points out of the material.
class RayIndex {
 public:
  explicit RayIndex(const std::vector<geom2d::Polygon>& polygons);
  // The signed distance t in [-reach, reach] of the boundary crossing nearest P on the line P + t·N
  // whose segment faces along +N (leaving the material as t grows); nullopt when none is in reach.
  std::optional<double> crossing(Vec2 p, Vec2 n, double reach) const;
  // Whether P lies in the material (winding number of the boundary, nonzero).
  bool inside(Vec2 p) const;
  bool empty() const { return segments_.empty(); }

 private:
  struct Segment {
    Vec2 a, b;
  };
  std::vector<Segment> segments_;
  double x0_ = 0, y0_ = 0, cell_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_;   // CSR grid: cell c holds cells_[start_[c] .. start_[c+1])
  std::vector<std::uint32_t> cells_;
};

}  // namespace polyaxis::lamination::detail
