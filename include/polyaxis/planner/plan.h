// The main job: from a repaired part, a machine and a process to a machine program and the
// figures an engineer checks (SPEC §1, §3). One region for now (the region tree comes with the
// geometry-reasoning issue): planar layers along one build direction.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/post/program.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/machine/build_model.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "polyaxis/slicing/slice.h"
#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::planner {

using core::Vec3;

// How a region's layers are made (--layers): parallel planes with adaptive thickness, tilted
// "3-D" layers along the region's centroidal axis (slicing::SliceOptions::tilted), conformal layers
// at even distances from the prebuilt part's surface (slicing/conformal.h; regions built onto a
// --substrate or --prebuilt part), or, per region, the one the support check favours
// (region_layers in plan.cpp).
enum class LayerChoice { kPlanar, kTilted, kConformal, kAuto };
const char* layer_choice_name(LayerChoice c);

// Why a region's layers are what they are (PlanRegion::layers_rule).
inline constexpr const char* kLayersAsked = "layers.asked";      // --layers planar|tilted|conformal
inline constexpr const char* kLayersPlanar = "layers.planar";    // auto: planar layers leave no overhang, or tilted ones do no better
inline constexpr const char* kLayersTilted = "layers.tilted";    // auto: tilted layers leave less overhang than planar ones
inline constexpr const char* kLayersConformal = "layers.conformal";  // auto: conformal layers leave less overhang than planar ones
// Auto layers: tilted or conformal layers are kept when they leave less than this share of the
// planar layers' overhang (the one of the two that leaves less).
inline constexpr double kTiltedGainShare = 0.5;
// Conformal layers: where the distance from the base bends over an edge of the region, the edge is
// bisected down to this many bead widths before the levels are cut (slicing::refined_for_levels).
inline constexpr double kConformalEdgeBeads = 0.5;

struct PlanOptions {
  Vec3 direction{0, 0, 1};   // build direction in the part's frame
  LayerChoice layers = LayerChoice::kAuto;
  bool tilt_on_overhang = true;  // Kapil Eq. 3 on overhanging surface contours (outer and hole) (needs rotary axes)
  int perimeters = 2;
  double retract_mm = 5.0;   // lift along the tool axis between layers
  int threads = 0;
  // Every head point stays this far above the substrate and the table (the tip itself may touch
  // the plate: it deposits there). Tool axes are turned towards the table's normal until it does.
  double head_clearance_mm = 0.5;
  // Set (by another thread) when the plan is no longer wanted: make_plan ends at its next stage
  // (before a region is sliced, before sequencing, before the program) with kInfeasible
  // "stopped". Null: it runs to its end.
  const std::atomic<bool>* stop = nullptr;
  // A solid of the part built before the regions that grow on it (PlanRegion::on_trunk), in the
  // part's frame: the base of their conformal layers, in place of a prebuilt part's surface. Set by
  // plan_part for branches grown on their trunk; null otherwise.
  std::shared_ptr<const mesh::Mesh> trunk;
  // False: make_plan leaves Plan::fidelity unmeasured (measure_plan_fidelity measures it later).
  // The automatic choice's candidates are made so: only the chosen one is measured.
  bool measure_fidelity = true;
};

// Support check (SPEC §3): a layer's area outside the layer below grown by t·tan(α), where α is
// the self-supporting angle measured from the torch axis. A tilted torch moves the local build
// direction: each piece of overhang is counted as supported when it lies within the layer below
// grown by t·tan(α + θ), θ the largest tilt of the surface-contour points over that piece (within a
// bead of it). With the torch along d everywhere this is the plain planar check.
// The rule of a region that is the whole part, along one direction (--strategy single).
inline constexpr const char* kRegionWhole = "whole part";

// One region of the part, built along its own direction (analysis::decompose gives these).
struct PlanRegion {
  std::uint32_t id = 0;
  mesh::Mesh mesh;          // closed, in the part's frame (before placement)
  Vec3 direction{0, 0, 1};  // build direction, in the same frame
  // For the report: the parent region (none for the root), a point of the base surface, and
  // whether the region is support-free in its own direction (analysis::Region's fields).
  std::optional<std::uint32_t> parent;
  Vec3 base_point;
  Vec3 base_normal{0, 0, 1};  // the base's normal, into the region (analysis::Region::base_normal)
  bool support_free = true;
  // Why the region exists and why its direction (the rule base, plan.json): the decomposition's
  // rule for its base (analysis::Region::rule, kRegionWhole for an undivided part), the regions it
  // rests on, its volume and its overhang along its own direction as the decomposition found them.
  std::string rule = kRegionWhole;
  std::vector<std::uint32_t> rests_on;
  double volume_mm3 = 0.0;
  double overhang_mm2 = 0.0;
  // The rule that turned the region off the direction its region rule gives (kDirectionRedirected)
  // and why, in words; both empty when it keeps that direction.
  std::string direction_rule;
  std::string direction_why;
  // The layers the region is built with, the rule that chose them (kLayers…) and the figures it
  // compared (the overhang slicing::overhang_estimate_mm2 finds for each strategy tried).
  slicing::LayerStrategy layers = slicing::LayerStrategy::kPlanar;
  std::string layers_rule = kLayersAsked;
  std::string layers_why;
  // Already on the table (`--substrate`, `--prebuilt`): not sliced or deposited; the build model
  // holds it (machine::PrebuiltBody), the support check counts it as built before every region,
  // and the regions resting on it start on its surface.
  bool prebuilt = false;
  // Grows on PlanOptions::trunk, which the regions before it build: its layers may follow the
  // trunk's surface (conformal layers), as a prebuilt part's.
  bool on_trunk = false;
};

// The rule of a region built along another direction than the decomposition's: along that one the
// head struck something that no build order or torch tilt cleared (plan_part).
inline constexpr const char* kDirectionRedirected = "direction.redirected";
// Directions tried for a redirected region differ from its own and from each other by at least
// this, degrees.
inline constexpr double kRedirectMinDeg = 5.0;

// The rule of a region that is a part already on the table (--substrate).
inline constexpr const char* kRegionSubstrate = "substrate";
// The rule of a deposited region laid onto a substrate (--substrate): the part less the substrate.
inline constexpr const char* kRegionOnSubstrate = "on the substrate";
// The rules of a part split into a trunk and the branches that grow on it (plan_part): the trunk
// when it is built as one region, and each branch.
inline constexpr const char* kRegionTrunk = "trunk";
inline constexpr const char* kRegionOnTrunk = "branch on its trunk";

struct LayerReport {
  std::uint32_t index = 0;
  std::uint32_t region = 0;
  double height_mm = 0.0;
  double thickness_mm = 0.0;
  double min_thickness_mm = 0.0, max_thickness_mm = 0.0;  // over the layer (slicing::Layer::thickness_range)
  double area_mm2 = 0.0;
  double unsupported_area_mm2 = 0.0;
  double max_tilt_deg = 0.0;
  std::uint32_t paths = 0;
  // The torch: deposit points whose axis leaves the layer's normal by more than kTiltedDeg, those
  // the planner turned for clearance or reach, and the rule that set the layer's tilt (kTilt…).
  std::uint32_t tilted_points = 0;
  std::uint32_t turned_points = 0;
  std::uint32_t eased_points = 0;  // tilts eased towards the normal where the head would strike the deposit
  std::string tilt_rule;
  // The pieces counted in unsupported_area_mm2, in the layer's (u, v) frame.
  std::vector<geom2d::Polygon> unsupported;
};

// The rules that place a layer in the build order (src/planner/sequence.h; Dwivedi Rules 2–4).
inline constexpr const char* kRuleStart = "order.root";          // the root region's first layer
inline constexpr const char* kRuleFather = "order.after-father";  // a child starts once its father and what its base rests on are complete
inline constexpr const char* kRuleContinue = "order.continue";    // the next layer of the region being built (Rule 4)
inline constexpr const char* kRuleLevel = "order.level";          // the lowest pending interference level, in region order (Rules 2–3)

// The rules that set a layer's torch axes (toolpath.h, Kapil Eq. 3; the build model's guard).
inline constexpr const char* kTiltNormal = "tilt.normal";        // along the layer's normal everywhere
inline constexpr const char* kTiltOverhang = "tilt.overhang";    // tilted over overhanging surface contours (outer and hole) (Kapil Eq. 3)
inline constexpr const char* kTiltClearance = "tilt.clearance";  // turned towards the table's normal for clearance or reach
inline constexpr const char* kTiltOnPlate = "tilt.on-plate";     // laid on the plate: upright
inline constexpr const char* kTiltEased = "tilt.eased";          // turned towards the normal or the table's to clear the deposit
// A deposit point's axis this far from the layer's normal counts as tilted.
inline constexpr double kTiltedDeg = 0.5;

// Interfering layers listed per layer, at most.
inline constexpr std::size_t kMaxListedInterference = 16;

// Why a layer is where it is in the build order.
struct LayerOrder {
  std::uint32_t region = 0;
  std::uint32_t region_layer = 0;  // 1-based within its region: Dwivedi's L_n of R_n
  // Interference level (Dwivedi's Gd): 0 when the layer's C-space contour overlaps no layer of
  // another region (other than its ancestors'); layers that interfere share levels.
  std::uint32_t level = 0;
  std::string rule;  // one of the kRule ids above
  // The layers (build-order indices) whose C-space contours overlap this one's, the first
  // kMaxListedInterference of `interferences`.
  std::vector<std::uint32_t> interferes_with;
  std::uint32_t interferences = 0;
};

// Wall-clock seconds of each stage of make_plan.
struct StageTimes {
  double slice_s = 0.0;
  double toolpath_s = 0.0;
  double program_s = 0.0;
  double support_s = 0.0;
  double sequence_s = 0.0;
  double fidelity_s = 0.0;
};

// Where the part stands on the table: table = rotation · part + translation. The rotation is the
// smallest one turning the build direction (the root region's) to the table's +Z; the translation
// puts the base at Z = 0 with the footprint centred on the rotary axis.
struct Placement {
  Vec3 rows[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // the rotation matrix, by rows
  Vec3 translation_mm;

  Vec3 rotate(Vec3 v) const { return {core::dot(rows[0], v), core::dot(rows[1], v), core::dot(rows[2], v)}; }
  Vec3 unrotate(Vec3 v) const { return rows[0] * v.x + rows[1] * v.y + rows[2] * v.z; }  // the transpose
  Vec3 apply(Vec3 p) const { return rotate(p) + translation_mm; }
};

// The smallest rotation turning D (any non-zero vector) to +Z; a half turn about X for −Z.
Placement rotation_to_z(Vec3 d);

// A reorientation of the program and the rule that made it (kReorient…).
struct Reorientation {
  std::uint64_t point = 0;  // the program point reached by the turn
  std::uint32_t layer = 0;
  double angle_deg = 0.0;
  std::string rule;
};
inline constexpr const char* kReorientRegion = "reorient.region";  // the next layer is another region's, along its direction
inline constexpr const char* kReorientLayer = "reorient.layer";    // the next layer of the region starts with another tilt
inline constexpr const char* kReorientTilt = "reorient.tilt";      // the torch tilt changes along a layer

// How closely the layers reproduce the part (SPEC §3; planner/fidelity.h says how it is measured).
struct Fidelity {
  double max_cusp_mm = 0.0;              // the largest staircase height
  double volume_difference_mm3 = 0.0;    // the symmetric difference between the deposited layers and the part
  double volume_difference_share = 0.0;  // of the part's volume
  bool measured = false;                 // false: not measured yet (PlanOptions::measure_fidelity)
};

struct Plan {
  StageTimes times;
  Fidelity fidelity;
  slicing::SliceResult layers;
  std::vector<toolpath::LayerToolpaths> toolpaths;
  std::vector<post::ProgramPoint> program;  // tool tip and axis, part frame
  std::vector<LayerReport> layer_reports;
  std::vector<std::uint32_t> region_of_layer;  // region id of each layer
  std::vector<LayerOrder> order;               // why each layer is where it is (indexed like layers)
  double c_space_radius_mm = 0.0;              // the head radius the C-space contours were grown by
  std::uint32_t regions = 1;
  // The regions as built, placed (the whole part as region 0 when no regions were given); a
  // region's support_free is cleared when one of its layers has unsupported area.
  std::vector<PlanRegion> placed_regions;
  Placement placement;        // part frame -> table frame; everything below is in the table frame
  machine::BuildModel build_model;  // the table, the plate (top at Z = 0) and the head
  // Tool axes turned towards the table's normal to keep the head clear of the plate or the table,
  // or inside the tilt axis's reach, and the first layers on the plate laid with the torch upright.
  std::uint64_t axes_turned = 0;
  // Tilts eased towards the layer's normal where the tilted head would strike the deposit, and
  // travel moves that leave the straight line to clear it (planner/clearance.h).
  std::uint64_t tilts_eased = 0;
  std::uint64_t travel_detours = 0;
  // Toolpath points turned after reading the program back (relieve_collisions), keyed by layer and
  // point (flat within the layer), with how far along the candidates each went.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> relieved;
  // Rounds in which relieve_collisions turned points and the program was made again: zero where
  // the planner's own checks (clearance.h) left nothing for the read-back to find.
  std::uint32_t relief_rounds = 0;
  double deposit_length_mm = 0.0;
  double travel_length_mm = 0.0;
  double unsupported_area_mm2 = 0.0;
  double max_tilt_deg = 0.0;
  std::uint64_t reorientations = 0;  // tool-axis changes of more than kReorientationDeg between points
  std::vector<Reorientation> reorientation_list;  // each of them, in program order
  std::uint64_t thin_regions = 0;
  double thin_area_mm2 = 0.0;
};

// A change of tool axis larger than this between consecutive program points counts as a
// reorientation (a distinct rotary move of the table).
inline constexpr double kReorientationDeg = 5.0;
// Unsupported area below this is snapping noise, not an overhang.
inline constexpr double kUnsupportedNoiseMm2 = 0.01;

// Where the program, read back, still strikes earlier deposit, or the plate or the table within a
// bead of a layer's path (PLACES: each a layer and the tip, verify::BuildCheck::collision_places),
// the torch at the layer's toolpath points nearest each place (the move's two ends) turns further
// — first along the layer's normal, then half way and all the way towards the table's normal
// within toolpath::kMaxTiltRad — keeping the plate, the table and the reach clear; the support
// check and the program are then made again. Each call takes every point one candidate further.
// Returns how many points turned (0: nothing left to try).
std::size_t relieve_collisions(Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                               const PlanOptions& options, const std::vector<std::pair<std::uint32_t, Vec3>>& places);

// A rule of the rule base (SPEC §2.9, Dwivedi §5–7): its id, what it says, and its parameters
// (from the process and the machine files), as plan.json lists them.
struct Rule {
  std::string id;
  std::string says;
  std::vector<std::pair<std::string, double>> parameters;
};

// The rules a plan's decisions name (regions, layer order, reorientations, torch tilt), with the
// parameters they had for PLAN.
std::vector<Rule> rule_base(const machine::MachineConfig& machine, const process::ProcessConfig& process, const Plan& plan);

// Places PART (turning it so that the build direction — the first region's — is the table's +Z,
// then translating it so that the first region's base sits on the substrate's top at Z = 0 and
// its footprint is centred on the rotary axis), slices it (adaptive thickness within the
// process's range when process.adaptive_layers, else at its layer height),
// makes toolpaths with the process's bead, checks support, and lists the program points.
// REGIONS (parents before children; empty: the whole part along options.direction) are built one
// after the other, each sliced along its own direction; layers are numbered across regions.
// Prebuilt regions (PlanRegion::prebuilt) come first, their ancestors prebuilt too: the first of
// them stands on the plate and the others are placed with it; none is sliced.
// Before slicing: a region reaching below the plate (kInfeasible) or built along a direction the
// tilt axis cannot reach (kMachineLimit) is refused, naming the region, the direction and the
// limit. Tool axes are kept inside the reach and the head clear of the plate and the table
// (PlanOptions::head_clearance_mm, machine/build_model.h); a point where no axis within
// toolpath::kMaxTiltRad of the layer's normal does is kMachineLimit.
// Errors: bad options (kUsage), nothing to build (kInfeasible).
core::Result<Plan> make_plan(const mesh::RepairedMesh& part, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                             const PlanOptions& options, const std::vector<PlanRegion>& regions = {});

// Measures PLAN.fidelity (planner/fidelity.h) against its placed regions, the prebuilt ones left
// out, and adds the time to PLAN.times.fidelity_s. make_plan calls it unless
// PlanOptions::measure_fidelity is false.
void measure_plan_fidelity(Plan& plan, const process::ProcessConfig& process);

}  // namespace polyaxis::planner
