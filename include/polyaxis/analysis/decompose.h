// Decomposition of a part into a tree of regions, each built support-free along its own
// direction (SPEC §2.3, Ruan et al. 2006 §4.1).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/repair.h"

namespace polyaxis::analysis {

struct Region {
  std::uint32_t id = 0;
  std::optional<std::uint32_t> parent;  // none for the root
  Vec3 build_direction{0, 0, 1};        // the reverse of the base surface's outward normal
  Vec3 base_point;                      // a point of the base plane (the cut, or the plate)
  Vec3 base_normal{0, 0, 1};            // the base plane's normal, pointing into the region
  mesh::Mesh mesh;                      // closed, outward
  double volume_mm3 = 0.0;
  double unsupported_area_mm2 = 0.0;    // overhang area in its own direction (0 when support-free)
  // Corners of its surface off its base, lowest among their neighbours along its direction with
  // the solid above them: its first layer there starts on nothing, however steep the facets around
  // (a keel or a spike pointing down). None when support-free; looked for only in a region whose
  // facets do not overhang.
  std::vector<Vec3> mid_air_starts;
  bool support_free = false;
  std::string rule;  // how its base was found: "plate", "below the plate", "planar face", "fallback plane",
                     // "overhang patch"
  std::vector<std::uint32_t> rests_on;  // the regions its base lies on (its parent among them): all built before it
};

// A planar face of the part that can carry the root region (--root-base FACE-ID).
struct BaseFace {
  std::uint32_t id = 0;  // stable for a given mesh: the face's index among all its planar faces
  Vec3 normal;           // unit, outward
  Vec3 point;            // a corner of one of its facets
  double area_mm2 = 0.0;
  std::uint32_t facets = 0;
};

struct RegionTree {
  std::vector<Region> regions;  // in build order: every region after those it rests on; regions[0] is the root
  std::vector<BaseFace> faces;  // the part's planar faces of at least kMinBaseFaceMm2, by id
  bool budget_exhausted = false;  // DecomposeOptions::work_budget_facet_visits ran out
  double work_facet_visits = 0.0; // the work done, in the same units
};

// Planar faces smaller than this are not listed in RegionTree::faces (nor accepted as a root base).
inline constexpr double kMinBaseFaceMm2 = 1.0;

// Where the root region stands (`--root-base`).
struct RootBase {
  enum class Kind {
    kAuto,    // the plate found from the axis (below)
    kLowest,  // the lowest point along root_direction (`z-min`): nothing is cut off below it
    kFace,    // the planar face FACE (a BaseFace id): the root builds along its inward normal
    kPlane,   // the plane (POINT, NORMAL): the root is the side NORMAL points to, built along it
  };
  Kind kind = Kind::kAuto;
  std::uint32_t face = 0;
  Vec3 point;
  Vec3 normal{0, 0, 1};
};

// The planar faces of MESH of at least kMinBaseFaceMm2. O(F).
std::vector<BaseFace> base_faces(const mesh::Mesh& mesh);

// The root region's build direction for BASE: DEFAULT_UP for kAuto and kLowest, the reverse of
// the face's outward normal for kFace, the plane's normal for kPlane. kUsage naming --root-base
// for a face id that is not listed or a zero or non-finite normal.
core::Result<Vec3> root_direction(const mesh::Mesh& mesh, const RootBase& base, Vec3 default_up);

struct DecomposeOptions {
  Vec3 root_direction{0, 0, 1};   // build direction of the root region with kAuto and kLowest
  RootBase root_base;
  double self_supporting_deg = 30.0;
  double face_normal_tolerance_deg = 10.0;  // Ruan: the splitting face's normal within 10° of the link
  // Work allowed, in facet visits (a screened candidate costs the host's facets, an exact cut
  // kExactCutVisitsPerFacet per facet); 0: no limit. When it runs out, splitting stops with the
  // regions found so far and RegionTree::budget_exhausted is set. A count, not a time: the result
  // is the same on any machine and at any thread count.
  double work_budget_facet_visits = 0.0;
  // Every split region's build direction stays within this angle (degrees) of the root's: once the
  // root stands on the table, the machine's tilt reach (planner::plan_part sets it from the machine
  // file). A region that no reachable direction holds keeps its overhang rather than a direction
  // the machine cannot take. 180: any direction.
  double reach_deg = 180.0;
  // The least thickness a region can be deposited with, mm (the process's least layer): a cut
  // leaving a piece thinner than this on average (a film of a face) is refused.
  double min_region_mm = 0.3;
  // The head against the plate: the least height (mm) above the root's base plane, along the root's
  // direction, at which the head can lay a region built at the given angle (radians) from the
  // root's direction. A split whose child reaches lower would bring the head down onto the plate:
  // it is refused. Null: the head is not considered (planner::plan_part sets it from the machine's
  // head, src/planner/reach.h least_layable_height_mm).
  std::function<double(double)> least_height_mm;
  // Set (by another thread) when the result is no longer wanted: the decomposition ends at its
  // next piece of work, as if its budget were spent. Null: it runs to its end.
  const std::atomic<bool>* stop = nullptr;
};

// What one exact cut (CGAL, exact kernel) costs against the work budget, per facet of the region cut.
inline constexpr double kExactCutVisitsPerFacet = 2000.0;

// Splits MESH into regions along AXIS (Ruan 2006 §4.1, checked by overhang; docs/analyze.md).
// MESH must be a solid whose surface does not cross itself beyond a few faces (cuttable_solid
// below finds one or says why not): CGAL's exact cuts are undefined on one that does.
//
//  * The root is built along root_direction from the plate: the downward planar face where the
//    axis's root branch starts (a body on feet: the body's underside), else the lowest one. Shells
//    below the plate become regions built the opposite way. options.root_base pins the base
//    instead: the lowest point, a listed planar face or a plane (see RootBase); shells on the
//    far side of a face or plane become regions built the opposite way, as below the plate.
//  * Split links are the break links and the first link of every child branch. For each, the
//    candidate planes are Ruan's splitting faces (planar faces with a concave boundary edge, normal
//    within face_normal_tolerance_deg of the link or its father link, projection overlapping the
//    link: Eq. 5), planar faces with a concave edge leaning less than 90° − α from the link, and
//    planes across the link and the branch stepped back from the branch's first node. A cut keeps
//    as the child only the piece holding the branch's nodes; every other piece stays with the
//    parent, so a plane never carves up other branches.
//  * Every candidate is screened without cutting (facet areas clipped at the plane, the child
//    found by connectivity); greedily, the split removing the most overhang is cut exactly (CGAL,
//    capped), ties going to Ruan's faces, then the plane most nearly across its link. The child's
//    build direction minimises its overhang, at most 90° − α from its base's normal. Splitting
//    stops when no split removes overhang.
//  * What the links leave is cut off patch by patch (largest first) into regions of their own,
//    along a direction in which the patch and its whole child stand, when that removes overhang
//    (rule "overhang patch"; src/analysis/patch_split.h). The plate is never taken.
//  * With options.least_height_mm, a split whose child reaches below the height at which the head
//    can lay it along its direction is refused (a column's half built sideways down to the plate).
// Regions partition MESH (volumes sum to its volume) and are closed; they come in build order:
// each after its parent and every region its base lies on (rests_on). A region that stays unsupported says so (support_free false, its area). Cost: O(F) per
// candidate screened plus one or a few CGAL cuts per region made; milliseconds for the reference parts.
core::Result<RegionTree> decompose(const mesh::Mesh& mesh, const CentroidalAxis& axis, const DecomposeOptions& options = {});

// The decomposition's exact cuts (CGAL corefinement) need a solid whose surface does not cross
// itself. A few crossing faces, where a part's pieces were fused imperfectly (two_branches: 16 of
// 6 744), are cut through where the plane misses them; a surface where more than this share of the
// faces cross is a pile of overlapping bodies, on which the cuts are undefined (CGAL can crash).
inline constexpr double kMaxCrossingShare = 0.01;

// The solid to decompose for PART: PART itself, or its overlapping bodies united
// (mesh::unite_overlapping_shells) when that leaves fewer faces crossing, held in UNITED. CROSSING
// is set to the solid's crossing faces. Error kInfeasible, naming them, when more than
// kMaxCrossingShare of its faces cross.
core::Result<const mesh::RepairedMesh*> cuttable_solid(const mesh::RepairedMesh& part, std::optional<mesh::RepairedMesh>& united,
                                                       std::size_t& crossing);

}  // namespace polyaxis::analysis
