// The head against the material deposited before it (issue 12, item 1): the head as solids of
// revolution about the tool axis, and a bounding-volume hierarchy over the program's deposit
// samples, each stamped with its place in the deposit order, so that one index answers "what laid
// before this point does the head strike" at any point of the program. Private to verify.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/machine/build_model.h"

namespace polyaxis::verify::detail {

using core::Vec3;

// The head model (nozzle cone, cylinder, head boxes) as profiles in (h, r): h along the tool axis
// from the tip, r from the axis. Cone and cylinder are exact; each head box is replaced by the
// solid it sweeps turning about the axis (its tool-frame X and Y turn with C on the machine), so
// the distance is exact for the nozzle and conservative for the boxes.
class HeadProfile {
 public:
  explicit HeadProfile(const machine::BuildModel& model);
  // Signed distance (mm) from the point TIP + D to the head whose tool axis is AXIS (unit):
  // negative inside. 1-Lipschitz. Cost: a few dozen flops per profile piece.
  double distance(Vec3 d, Vec3 axis) const;
  // False when no point within REACH of the head can lie in the box [LO, HI] (whose points are
  // within RHO of its centre C): per piece, the box's extent along the axis against the piece's,
  // then a lower bound of the distance from C (the largest distance to an edge's line).
  bool may_touch(Vec3 lo, Vec3 hi, Vec3 c, double rho, Vec3 tip, Vec3 axis, double reach) const;

 private:
  struct Edge {
    double ax, ay, ex, ey;  // start and direction
    double nx, ny;          // outward unit normal
    double inv_len2;
  };
  struct Piece {
    std::vector<Edge> edges;  // convex, counter-clockwise in (h, r)
    double h_min = 0.0, h_max = 0.0;
  };
  std::vector<Piece> pieces_;
};

struct MaterialSample {
  std::array<float, 3> position;  // part frame, mm
  std::uint32_t stamp = 0;        // its place in the deposit order
  std::int32_t layer = 0, region = 0;
};

// The prebuilt body's surface as material laid before the whole program: one ball of RADIUS per
// surface point, its centre half a radius inside the surface (the balls' union covers the surface
// when the points are at most 0.84 radius apart, and bulges at most half a radius out of it);
// stamps 0, 1, … and layer and region −1 (kPrebuiltLayer).
inline constexpr std::int32_t kPrebuiltLayer = -1;
std::vector<MaterialSample> prebuilt_material(const machine::PrebuiltBody& body, double radius);

struct MaterialHit {
  std::size_t sample = 0;  // index into the samples given to the index
  double depth_mm = 0.0;   // how far the material's ball reaches into the head (may be < 0 within the margin)
};

// A static bounding-volume hierarchy over deposit samples (median splits, leaves of a few
// samples), each node holding the smallest stamp below it, so that material laid later is pruned
// whole. Building is O(n log n), its top levels in parallel, in a preorder layout that does not
// depend on the thread count; a query visits the nodes within reach of the head.
class MaterialIndex {
 public:
  // Samples of a prebuilt part (layer kPrebuiltLayer) are left out within PREBUILT_IGNORE_MM of the
  // tip (when less than a query's IGNORE_MM): the part is not the bead being laid.
  explicit MaterialIndex(std::vector<MaterialSample> samples, double prebuilt_ignore_mm = std::numeric_limits<double>::infinity());
  const MaterialSample& sample(std::size_t i) const { return samples_[i]; }
  std::size_t size() const { return samples_.size(); }

  // The deepest sample laid before BEFORE (stamp < BEFORE) and farther than IGNORE_MM from TIP
  // whose ball of RADIUS_MM comes within MARGIN_MM + TURN_RAD · (its distance from the tip) of
  // the head at (TIP, AXIS); none when there is none. With ANY, the first such sample found
  // instead of the deepest (a yes-or-no question answered without visiting the rest).
  std::optional<MaterialHit> deepest(const HeadProfile& head, Vec3 tip, Vec3 axis, std::uint32_t before, double radius_mm,
                                     double ignore_mm, double margin_mm, double turn_rad, bool any = false) const;

 private:
  struct Node {
    std::array<float, 3> lo, hi;
    std::array<float, 3> centre;  // of the box, and its half diagonal (rounded up): the bounding ball
    float rho = 0.0f;
    std::uint32_t min_stamp = 0;
    std::uint32_t first = 0, count = 0;  // samples [first, first + count) of a leaf
    std::uint32_t left = 0, right = 0;   // children of an inner node (count == 0)
  };
  std::uint32_t subtree_nodes(std::uint32_t count);
  static Node finish(Node node);  // sets the bounding ball from the box
  // Builds the subtree ID over samples [FIRST, FIRST + COUNT), whose box lies within [LO, HI] (the
  // parent's box cut at its split: the split axis is chosen on it), and sets its exact box from its children's.
  void build(std::uint32_t id, std::uint32_t first, std::uint32_t count, int depth, std::array<float, 3> lo, std::array<float, 3> hi);

  std::vector<MaterialSample> samples_;
  double prebuilt_ignore_mm_;
  bool has_prebuilt_ = false;
  std::vector<Node> nodes_;
  std::map<std::uint32_t, std::uint32_t> subtree_sizes_;  // nodes of a subtree of so many samples
};

// A shortcut for the commonest check, exact under the margins of MaterialIndex::deepest: the head
// lies on its tip's side of the plane through the tip square to its axis a (the cone and the
// cylinder grow along a from the tip; a head box reaching below the tip turns the shortcut off).
// When every ball laid before a check has its centre at most h above that plane, and h is small
// enough that no point at most h above it and farther than the ignored distance from the tip comes
// within the check's reach of the head, the check is clear without a search. The greatest height of
// the deposit laid so far is kept per stamp along each of AXES (a planar region's layers share
// one; checks along other axes are not shortened). Memory: one double per sample and axis.
class BelowTheTip {
 public:
  // MATERIAL in stamp order (material[i].stamp == i); RADIUS and IGNORE as given to deepest.
  BelowTheTip(std::vector<std::array<float, 3>> axes, const std::vector<MaterialSample>& material, const machine::BuildModel& model,
              double radius, double ignore);
  // True when nothing laid before BEFORE can come within RADIUS + MARGIN_MM + TURN_RAD · (its
  // distance) of the head at (TIP, AXIS) farther than IGNORE from the tip: deepest would find none.
  bool clear(const std::array<float, 3>& tip, const std::array<float, 3>& axis, std::uint32_t before, double margin_mm, double turn_rad) const;

 private:
  struct Track {
    std::array<float, 3> axis;
    std::vector<double> highest;  // by stamp: the greatest height along the axis of the deposit laid before
  };
  double radius_, ignore_, cone_rad_ = 0.0, above_cone_mm_ = 0.0, extent_ = 0.0;
  std::vector<Track> tracks_;
};

}  // namespace polyaxis::verify::detail
