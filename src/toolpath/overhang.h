// Kapil et al. Eq. 1-3: the torch axis on surface contours (outer and hole) over overhanging facets, and the lookup
// of the facet under a contour point.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/slicing/layer.h"
#include "polyaxis/slicing/section.h"

namespace polyaxis::toolpath::detail {

using core::Vec3;

// The segments where the mesh's faces cross one layer plane, in the plane's (u, v) frame (mm),
// bucketed in a uniform grid for nearest-segment queries.
class FacetLocator {
 public:
  // FACES: candidates that may cross the plane at height H_MM along the context's direction (a
  // superset is fine). A face is crossed under section.h's tie rule (corner above when its height
  // is >= h), at edge points built as slicing::section builds them. Cost: O(|faces| + cells).
  FacetLocator(const slicing::SectionContext& context, double h_mm, const slicing::Frame& frame,
               std::span<const std::uint32_t> faces);

  bool empty() const { return segments_.empty(); }

  struct Nearest {
    std::uint32_t face;
    double tu, tv;  // unit direction of the face's crossing segment, solid to its left
  };
  // The face whose crossing segment is nearest to (U_MM, V_MM), and that segment's direction as
  // slicing::section runs it (outer loops counter-clockwise about d). Ties go to the face crossed
  // first in FACES order. Precondition: !empty(). Cost: the segments in the cells searched,
  // typically O(1).
  Nearest nearest(double u_mm, double v_mm) const;

 private:
  struct Segment {
    double ax, ay, bx, by;
    std::uint32_t face;
  };
  std::vector<Segment> segments_;
  double x0_ = 0.0, y0_ = 0.0, cell_mm_ = 1.0;
  std::int64_t nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_;  // cell c holds items_[start_[c] .. start_[c + 1])
  std::vector<std::uint32_t> items_;
};

// Kapil Eq. 3 for one move. N: the facet's unit outward normal; TANGENT: the contour's direction
// p_{i+1} − p_i on that facet (world, any length); D: the unit build direction; MIN_DOT: the facet
// overhangs when n·d < MIN_DOT (= −sin α for the self-supporting angle α). Returns d on a facet
// that does not overhang or when n × tangent vanishes; else n × tangent normalised (Eq. 1),
// flipped if it points below the layer (t·d < 0: a contour run clockwise about d), and turned
// towards d so its angle from d is at most kMaxTiltRad. Always a unit vector.
Vec3 torch_axis(Vec3 n, Vec3 tangent, Vec3 d, double min_dot);

}  // namespace polyaxis::toolpath::detail
