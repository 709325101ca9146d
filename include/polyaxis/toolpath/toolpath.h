// Toolpaths for planar layers (SPEC §2.5): perimeters, area fill, ordering and a tool axis at every
// point. Planar 5-axis tool axes follow Kapil et al., "5-axis slicing methods for additive
// manufacturing of metallic parts", Eq. 1-3: on a surface-contour point over an overhanging facet
// the torch is t = n × (p_{i+1} − p_i), normalised; elsewhere t = k (the build direction).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::toolpath {

using core::Vec3;

// The largest angle between a tool axis and the layer normal d that make_toolpaths emits, radians
// (60°). Kapil's Eq. 3 tilts the torch by the full overhang angle, which reaches 90° on a facet
// facing straight down; no deposition torch works lying flat (the melt pool runs off and the
// nozzle body hits the layer), and 60° is the usual reach of a table-table 5-axis head. A steeper
// overhang is tilted to this limit, in the plane spanned by d and Kapil's t.
inline constexpr double kMaxTiltRad = 60.0 * 3.14159265358979323846 / 180.0;

// A piece of a section that the first half-bead offset loses is reported as thin when its area is
// at least this many squared bead widths. Smaller pieces are the tips of acute corners cut by the
// mitre limit of the offsets (a 30° corner loses ≈ 0.23 w²), not features of the part.
inline constexpr double kThinMinAreaBeads2 = 0.25;

// Gap fill: a piece too thin for a perimeter gets one bead along its middle (detail::centre_lines)
// where it is at least this many bead widths wide. The bead is a full bead, so a feature of half a
// bead comes out a bead wide (a hybrid cell machines it back); narrower ones are not deposited.
inline constexpr double kGapFillMinWidthBeads = 0.5;

// The lost pieces are measured against the opened section grown by this much, mm (1 µm), so the
// nanometre slivers left by rounding offsets to the 1 nm grid are not counted as pieces.
inline constexpr double kThinSlackMm = 1e-3;

// On conformal layers the paths, made on the layer's projection, are cut into moves no longer than
// this many bead widths before they are lifted onto the curved surface (a chord of c mm over a
// surface of radius R mm sags c²/8R: 0.025 mm for a 2 mm bead's 1 mm on R = 5 mm).
inline constexpr double kDrapeStepBeads = 0.5;

struct PathPoint {
  Vec3 position_mm;  // world (part) frame, on the layer's plane (its mid-plane), mm
  Vec3 tool_axis;    // unit, from the tool tip up the nozzle
  bool deposit = false;  // process on for the move arriving at this point
};

enum class PathKind { kPerimeter, kFill, kTravel };

struct Path {
  PathKind kind = PathKind::kPerimeter;
  std::uint32_t layer = 0;            // Layer::index
  std::uint32_t region = 0;           // ToolpathOptions::region
  // Perimeters: 0 = outermost. Contour-parallel fill rings continue the count (perimeters + j for
  // the j-th fill ring); zigzag fill and travel: 0.
  std::uint32_t perimeter_index = 0;
  bool surface_contour = false;  // the outermost perimeter of a boundary, outer or hole: it lays the part's surface
  bool gap_fill = false;       // a fill path laid along the middle of a thin piece (ToolpathOptions::gap_fill)
  // Closed paths (perimeters, contour fill) repeat their first point at the end. The first point
  // of every deposition path has deposit = false (the move arriving there is a travel).
  std::vector<PathPoint> points;
};

// A part of a section too thin for one bead that no bead covers (no perimeter, and no gap fill:
// narrower than kGapFillMinWidthBeads, or beyond the gap fill's line), so it is not deposited.
// Reported, never silently dropped (RELIABILITY G2).
struct ThinRegion {
  std::uint32_t layer = 0;  // Layer::index
  Vec3 where_mm;            // the piece's area centroid, world frame, on the layer plane
  double area_mm2 = 0.0;
  std::string what;         // e.g. "island narrower than a bead (2 mm): no perimeter fits"
};

struct ToolpathOptions {
  double bead_width_mm = 2.0;  // deposited bead width, > 0
  int perimeters = 2;          // closed perimeters per island, >= 0
  enum Fill { kZigzag, kContour, kNone };
  Fill fill = kZigzag;         // area fill inside the perimeters
  // Zigzag scan direction in the layer's (u, v) frame, degrees from u; layer k scans at
  // fill_angle_deg + 90°·(k mod 2).
  double fill_angle_deg = 0.0;
  // Neighbouring beads overlap by this fraction of the bead width, in [0, 1): perimeters and fill
  // lines are spaced by bead_width_mm·(1 − overlap).
  double overlap = 0.0;
  bool tilt_on_overhang = true;  // Kapil Eq. 3 on surface contours (outer and hole); false: t = d everywhere
  // Self-supporting angle α from the build direction, degrees, in [0, 90). A facet with unit
  // normal n overhangs when n·d < −sin α, i.e. when its wall leans more than α from d. With α = 0
  // this is Kapil's Eq. 2 (n·k < 0); Kapil notes (§3-axis slicing) that walls within about 30° of
  // vertical build without tilting, which is the default (core::kDefaultSelfSupportingDeg).
  double self_supporting_deg = 30.0;
  // Pieces too thin for a perimeter get one bead along their middle (kGapFillMinWidthBeads), run
  // as open fill paths after the island's perimeters; false: they are only reported. Above the
  // first layer of a make_toolpaths call the line is kept only where it lies within
  // max(t·tan(self_supporting_deg), max_step_mm) of the centre lines of the layer below's beads (t
  // the distance between parallel layers' planes, a tilted layer's least thickness; seen along its
  // normal): a bead never starts over a thin piece that was not laid, and a line steps out from the
  // one below no further than the support check lets a wall step (planner/support.h).
  // On conformal layers the paths are planned on the section warped to the surface (SurfaceWarp),
  // and the beads below are seen along the layer's normal and warped alike. The same bead fills the
  // gap a perimeter leaves where the next cannot follow it (at least kGapFillMinWidthBeads wide).
  bool gap_fill = true;
  // The sideways step a bead may take from the one below whatever the angle (the process's
  // max_step_bead_share × bead width, at most half a bead: the bead then still rests on the one
  // below by half its width); 0: t·tan(self_supporting_deg) alone.
  double max_step_mm = 0.0;
  // false: the call's first layer gets no gap fill either, for a first layer that does not stand
  // on the plate (what it rests on is not known here; the planner sets it per region).
  bool gap_fill_first_layer = true;
  std::uint32_t region = 0;  // copied into Path::region
  int threads = 0;           // 0: all cores (oneTBB); the output does not depend on it
  // The tilted torch's field along a surface contour (smooth_tool_axes): the largest tilt within
  // axis_window_mm of arc length on either side is held (no chatter between facets), and the tilt
  // ramps down no faster than max_axis_turn_deg_per_mm, so the rotary axes keep pace with the tip.
  double axis_window_mm = 1.0;
  double max_axis_turn_deg_per_mm = 3.75;
};

// The tool-axis field of one closed (CLOSED) or open contour, smoothed in place: the lean of each
// axis from D (its component across D) is replaced by the largest lean within WINDOW_MM of arc
// length on either side, in the mean lean direction there; then the tilt falls off from every
// point at most TURN_DEG_PER_MM (both ways round a closed loop). Tilts only grow, so an overhang
// that was tilted stays tilted. POINTS and AXES have the same size; axes are unit. O(n·window).
void smooth_tool_axes(const std::vector<Vec3>& points, std::vector<Vec3>& axes, Vec3 d, bool closed, double window_mm,
                      double turn_deg_per_mm);

struct LayerToolpaths {
  std::uint32_t layer = 0;         // Layer::index
  std::vector<Path> paths;         // in execution order, travel paths between deposition paths
  std::vector<ThinRegion> thin;
  double deposit_length_mm = 0.0;  // total length of the moves with deposit = true
  double travel_length_mm = 0.0;   // total length of the travel paths
  std::uint32_t axes_turned = 0;   // tool axes the planner turned for clearance or reach (planner/plan.h)
  std::uint32_t axes_eased = 0;    // tilts the planner eased to clear the deposit (planner/plan.h)
};

// Checks OPTIONS (kUsage naming the option).
core::Status validate(const ToolpathOptions& options);

// Toolpaths for every layer of LAYERS, in the same order (one LayerToolpaths per layer, empty
// paths for an empty layer). MESH is the mesh the layers were sliced from (mesh::repair output):
// its facets give the overhang tilt of surface contours (outer and hole). All layers must share one build direction
// (a SliceResult from slicing::slice or its adaptive form does).
//
// Per island (polygon) of a layer: perimeters at offsets w/2 + j·s inwards (w the bead width, s
// = w·(1 − overlap)), then gap fill (ToolpathOptions::gap_fill: the pieces the first perimeter's
// bead does not reach, or the whole island when no perimeter fits, each one bead along its
// middle), then fill. Zigzag fill scans the innermost perimeter's bead edge (offset
// w/2 + N·s − s/2) with lines s apart, the first s/2 inside, joined in boustrophedon order along
// the boundary between neighbouring lines. Contour fill continues the perimeters until the offset
// is empty. Seams of closed paths start at the vertex nearest to a point that turns by the golden
// angle about the layer's centroid from layer to layer. Islands and paths are ordered greedily by
// the nearest start.
//
// Tool axes: d (the layer normal) everywhere, except on surface-contour points when
// tilt_on_overhang. For the move from path point i to i + 1, the facet is the one whose crossing
// with the layer's plane is nearest to the move's midpoint (faces with face_min < h <= face_max,
// found through a uniform grid); if it overhangs (n·d < −sin α), point i gets
// t = n × (p_{i+1} − p_i) normalised (Kapil Eq. 1/3), where p_i → p_{i+1} is the part's contour
// on that facet, run as slicing::section runs it (solid on the left, so outer loops turn
// counter-clockwise about d like the perimeters). With n pointing out and down, this t leans
// from d outwards by the wall's angle from d, along the wall: up and away from the part. It is
// flipped if t·d < 0 (not expected on a closed outward mesh) and limited to kMaxTiltRad from d.
// Closed paths give their last point (the repeated first) the first point's axis; travel points
// take the axes of the points they join.
//
// Conformal layers (LAYERS.conformal_base set, slicing/conformal.h): the paths are made on each
// layer's projection as above, then carried onto its surface, their axes the distance's gradient
// (no overhang tilt); kInfeasible when a deposit point cannot be lifted.
//
// Layers run in parallel (oneTBB); the output is the same at any thread count. Layers of one
// direction share the facet buckets; tilted layers (each its own direction) find their facets
// alone, O(F) more a layer.
// Errors: kUsage for bad options. Cost per layer: the polygon
// offsets (O(n log n) each, perimeters + fill rings of them) plus O(p²) greedy ordering for p paths.
core::Result<std::vector<LayerToolpaths>> make_toolpaths(const mesh::Mesh& mesh, const slicing::SliceResult& layers,
                                                         const ToolpathOptions& options);

}  // namespace polyaxis::toolpath
