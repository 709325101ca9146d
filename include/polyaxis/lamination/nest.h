// Nesting pieces onto sheets (Hayasi §4, SPEC §2.8) with libnest2d's no-fit-polygon placer.
//
// libnest2d's clipper backend computes no-fit polygons of convex shapes only (two non-convex pieces
// come out overlapping, and so did a 1024-sided circle), so each piece is nested by the 72-sided
// polygon circumscribing its convex hull grown by half the spacing: 5° sides, within 0.1 % of the
// grown hull, unchanged by a quarter turn. No piece goes into another's hole or bay. The outlines
// are nested into the sheet shrunk by half the spacing, turned by multiples of 90°, so two pieces
// stand at least the spacing apart and every piece at least the spacing from the sheet's edge. The
// result is checked with exact integer
// booleans before it is returned.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/geom2d/polygon.h"

namespace polyaxis::lamination {

struct NestOptions {
  double sheet_w_mm = 300.0;
  double sheet_h_mm = 300.0;
  double spacing_mm = 3.0;   // least distance between pieces, and from a piece to the sheet's edge
};

// Where a piece goes: its point p lands on R(rotation)·p + (dx, dy) on sheet SHEET, whose corner is
// (0, 0) and which spans [0, w] × [0, h].
struct Placement {
  std::uint32_t sheet = 0;
  double rotation_deg = 0.0;  // 0, 90, 180 or 270
  double dx_mm = 0.0, dy_mm = 0.0;
};

// P placed by PLACEMENT.
void place(const Placement& placement, double x, double y, double& out_x, double& out_y);
geom2d::Ring place(const Placement& placement, const geom2d::Ring& ring);

// Nests OUTLINES (outer rings, counter-clockwise) onto as few sheets as the placer finds. kUsage
// for a bad sheet or spacing; kInfeasible naming the first piece that fits no sheet at any turn.
// Deterministic (single-threaded placer).
core::Result<std::vector<Placement>> nest(const std::vector<geom2d::Ring>& outlines, const NestOptions& options);

}  // namespace polyaxis::lamination
