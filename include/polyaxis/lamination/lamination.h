// Sheet lamination with sloped edges (Hayasi & Asiabanpour 2012; SPEC §2.4 "sloped-edge", §2.8):
// a part cut into thick layers taken from a stock of sheet thicknesses, each layer's edge cut by a
// tilted jet so that it follows the part's surface instead of a vertical stair step.
//
// The model, per layer [z0, z1] (the part's +Z is the stacking direction):
//
// - The layer is split into m thin sub-slices of at most `subslice_mm` (Hayasi's thin slices).
// - Its reference contour is the part's section at the layer's middle z_ref (the middle of the part's
//   span in the layer, in a last layer standing above the part's top). Every sample p of it
//   (its corners, and points every `sample_mm` along long edges) has an outward normal n (the
//   bisector of its edges' right-hand normals: away from the material, for outer loops and holes).
// - The edge profile at p is r(h): how far along n the part's boundary lies at height h, found by a
//   2-D ray from p along ±n in the section at h (only boundary crossings that leave the material
//   along +n count, across the whole part; a height with no material along the ray puts no bound
//   on the cut).
// - A cut is a straight jet line in the vertical plane through p along n: r(h) = r_ref + slope·(h −
//   z_ref). Its cutting vector is V = C × N of the facet the profile crosses (Hayasi Eq. 1; C the
//   contour vector, N the facet normal, both loops traced counter-clockwise as Hayasi traces them,
//   so V = N × C on outer loops and C × N on inner ones, pointing up along the surface), taken in the
//   section's normal plane at p (V's component along the contour dropped; on a smooth contour the two
//   agree). The program's tool axis is V, from the cut up to the head.
// - Convex edges (the profile bulges out: r concave in h over the sub-slices, Hayasi §3-3/3-4) are
//   cut once per sub-slice k, each along the facet's line at the sub-slice's middle height: the
//   kept material is bounded by the lowest of these lines, which lie outside a convex profile.
//   Concave, straight and mixed edges, and profiles where the material ends or steps within the
//   layer, are cut once, along the line within the jet's limit that keeps the least material beyond
//   the profile without leaving a point of it outside (the chord from bottom to top on a concave or
//   straight profile; vertical or at the limit at a step, whichever keeps less).
// - No gouge: every line is moved out until no profile point is outside it. A line steeper than the
//   jet's limit is cut at the limit and moved out likewise (counted as at the limit): the layer keeps
//   excess material there, never less than the part. A hole that would close within the layer is
//   not cut (Layer::holes_closed).
// - The kept edge at height h is then min over the sample's cuts of r(h); the kept section at h is
//   the polygon of the reference samples moved out by it.
//
// Layer choice (Hayasi §3-1): from the bottom, each layer takes the thickest sheet for which the
// area deviation of its sloped edge, max over heights h in the layer of A(S(h) Δ E(h)) / A(S(h)) (S
// the part's section, E the kept section), is within `area_deviation`, and, when `cusp_mm` is set,
// the largest gap between a cut and a profile sample is within it; the thinnest sheet when none is.
// Heights above the part's top count in the deviation volumes, not in the ratio.
// A top thinner than the thinnest sheet gets the thinnest sheet (its excess is reported).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "polyaxis/core/progress.h"
#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"
#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::lamination {

using core::Vec3;

struct Vec2 {
  double x = 0.0, y = 0.0;
};

struct LaminateOptions {
  std::vector<double> sheets_mm;       // the stock of sheet thicknesses (any order, each > 0)
  double area_deviation = 0.05;        // largest A(S Δ E)/A(S) over a layer (see above)
  std::optional<double> cusp_mm;       // largest gap between a cut and the part's profile, when set
  double subslice_mm = 0.0;            // thin sub-slice; 0: the thinnest sheet
  double sample_mm = 1.0;              // largest spacing of edge samples along a contour
  double max_jet_angle_deg = 45.0;     // the jet's largest tilt from vertical (the machine's A or B range)
  int threads = 0;                     // worker threads of this call; 0: all cores. The result does not depend on it
  core::ProgressCallback progress;     // the call's stages go here instead of stderr (core/progress.h)
};

// One straight jet line through an edge sample: the kept edge r(h) = r_mid_mm + slope·(h − z_ref).
struct Cut {
  double r_mid_mm = 0.0;
  double slope = 0.0;  // dr/dh: tan of the line's tilt from vertical, positive leaning out
};

enum class EdgeKind : std::uint8_t { kStraight, kConvex, kConcave };

struct EdgeSample {
  Vec2 p;                  // on the reference contour, mm, part frame (x, y)
  Vec2 n;                  // unit outward normal
  EdgeKind kind = EdgeKind::kStraight;
  std::vector<Cut> cuts;   // one (straight, concave) or one per sub-slice (convex)
  bool at_jet_limit = false;  // steeper than the jet's limit: cut at the limit
  double gap_mm = 0.0;        // largest distance (along n) from the kept edge out to a profile sample
  // Hayasi's machine angles of the sample's first cut's vector V (Eq. 1), degrees:
  // A = 180° − ∠(Z, V), C = ∠(X, V) with the sign of V's y.
  double hayasi_a_deg = 180.0, hayasi_c_deg = 0.0;
  double kept_mm(double h, double z_ref) const;  // min over the cuts of r(h)
};

struct EdgeLoop {
  bool hole = false;
  std::vector<EdgeSample> samples;  // in the ring's order (outer CCW, holes CW, seen from +Z)
  int passes() const;               // cuts of a convex sample (1 when none is convex)
};

// A piece: one connected part of a layer's reference section, with its holes.
struct Piece {
  EdgeLoop outer;
  std::vector<EdgeLoop> holes;
  double area_mm2 = 0.0;  // of the reference section
};

struct Layer {
  std::uint32_t index = 0;
  double z_bottom_mm = 0.0;
  double thickness_mm = 0.0;
  std::uint32_t subslices = 1;
  double area_deviation = 0.0;  // as defined above, for the layer taken
  double max_gap_mm = 0.0;      // the largest EdgeSample::gap_mm
  double excess_mm = 0.0;       // how far the layer's top stands above the part's top (the last layer)
  // The reference contour's height: the middle of the part's span in the layer (the layer's middle
  // except in a last layer standing above the part's top). Cuts are written about it.
  double z_ref_mm = 0.0;
  std::uint32_t convex_samples = 0, concave_samples = 0, straight_samples = 0, at_jet_limit = 0;
  // Holes left uncut: the hole narrows within the layer faster than a line within the jet's limit
  // can follow, so its cuts would cross it; the layer keeps the material (excess, never a gouge).
  std::uint32_t holes_closed = 0;
  std::vector<Piece> pieces;
  double z_top() const { return z_bottom_mm + thickness_mm; }
};

struct Lamination {
  std::vector<Layer> layers;
  double part_volume_mm3 = 0.0;
  // Volumes of the symmetric difference with the part, integrated over every layer's height:
  // the sloped-edge stack, and the same layers with vertical edges at their mid-height section.
  double sloped_deviation_mm3 = 0.0;
  double stepped_deviation_mm3 = 0.0;
  // The same layers with vertical edges that keep all their material (the union of the part's
  // sections over each layer's height): the stair step that, like the sloped edge, never gouges.
  double covering_deviation_mm3 = 0.0;
  bool threshold_met = true;  // false when some layer took the thinnest sheet without meeting the limits
};

// Laminates MESH (closed, outward: mesh::repair output) along +Z. kUsage for an empty stock, a
// non-positive thickness or bad options; kInfeasible for a part with no section. Deterministic.
core::Result<Lamination> laminate(const mesh::Mesh& mesh, const LaminateOptions& options);

// The kept section of PIECE at height H (mm) in LAYER: the reference samples moved out along their
// normals by the kept edge, outer ring and holes; nonzero union. OFFSET_MM moves every edge out
// further (the jet's half kerf, for the path of the jet's centre).
std::vector<geom2d::Polygon> kept_section(const Layer& layer, const Piece& piece, double h, double offset_mm = 0.0);

}  // namespace polyaxis::lamination
