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

// A point this close behind a boundary (mm) is on it: the reference contour lies on its own section.
inline constexpr double kOnBoundaryMm = 1e-6;

// Faces bucketed by height so that a section at any height reads only the faces that may cross it.
class SectionStack {
 public:
  explicit SectionStack(const mesh::Mesh& mesh);
  // The part's section at H (nonzero union, outer CCW, holes CW), thread-safe.
  std::vector<geom2d::Polygon> at(double h) const;
  double min_z() const { return context_.min_height(); }
  double max_z() const { return context_.max_height(); }
  double diagonal_mm() const { return diagonal_mm_; }  // of the part's bounding box

 private:
  slicing::SectionContext context_;
  double bin_mm_ = 1.0;
  double diagonal_mm_ = 0.0;
  std::vector<std::vector<std::uint32_t>> bins_;  // faces whose height range meets each bin
};

// The boundary segments of one section in mm, in a uniform grid, for rays from points of another
// section. Every segment runs with the material on its left (section.h), so its right-hand normal
// points out of the material.
class RayIndex {
 public:
  explicit RayIndex(const std::vector<geom2d::Polygon>& polygons);
  // The boundary's offset along N from P: walking from P along +N to the first boundary, a boundary
  // that leaves the material means P is in it and the material reaches that far (t ≥ 0); otherwise
  // walking back along −N, a first boundary with the material behind it means the material has
  // retreated that far (t < 0); nullopt when neither (no material on the line near P). Boundaries
  // within kOnBoundaryMm behind P count as at P. Only the grid cells along the line are read.
  std::optional<double> offset(Vec2 p, Vec2 n) const;
  bool empty() const { return segments_.empty(); }

 private:
  struct Segment {
    Vec2 a, b;
  };
  struct Hit {
    double t = 0.0;
    bool leaves = false;  // the segment's outward normal points along the walk
  };
  // The first boundary along P + t·D, t ≥ −kOnBoundaryMm (a grid walk).
  std::optional<Hit> first_hit(Vec2 p, Vec2 d) const;
  std::vector<Segment> segments_;
  double x0_ = 0, y0_ = 0, cell_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_;   // CSR grid: cell c holds cells_[start_[c] .. start_[c+1])
  std::vector<std::uint32_t> cells_;
};

}  // namespace polyaxis::lamination::detail
