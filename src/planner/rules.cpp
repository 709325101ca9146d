// The rule base as plan.json lists it (SPEC §2.9): every rule id the planner records, in words,
// with the parameters it ran with.
#include <cmath>
#include <numbers>

#include "polyaxis/planner/plan.h"
#include "polyaxis/slicing/conformal.h"
#include "branches.h"
#include "clearance.h"
#include "reach.h"

namespace polyaxis::planner {

std::vector<Rule> rule_base(const machine::MachineConfig& machine, const process::ProcessConfig& process, const Plan& plan) {
  const double reach_deg = detail::direction_reach_rad(machine, process) * 180.0 / std::numbers::pi;
  const double alpha = process.self_supporting_deg;
  return {
      {kRegionWhole, "the part is built as one region along one direction (--strategy single, or the better plan of --strategy auto)", {}},
      {"plate", "the root region stands on the substrate plate: its base is the part's face on the plate", {}},
      {"root base (face)", "the root region stands on the planar face given by --root-base, built along its inward normal", {}},
      {"root base (plane)", "the root region is the side of the plane given by --root-base that its normal points to", {}},
      {"planar face",
       "a region needs its own direction where the centroidal axis breaks (Ruan §4.2.1): it is cut off at a planar face of the part, "
       "and built along the face's inward normal",
       {{"self_supporting_deg", alpha}, {"reach_deg", reach_deg}}},
      {"fallback plane",
       "a region needs its own direction where the centroidal axis breaks and no planar face bounds it: cut by the plane normal to the "
       "axis there, and built along that normal",
       {{"self_supporting_deg", alpha}, {"reach_deg", reach_deg}}},
      {"overhang patch",
       "a region needs its own direction where an overhang patch cannot be built along its parent's: split off along the patch's "
       "silhouette and built along the direction that leaves the least overhang within the reach",
       {{"self_supporting_deg", alpha}, {"reach_deg", reach_deg}}},
      {"below the plate", "the part below the root's base is a region of its own, built after the root from the cut upwards", {}},
      {kRegionSubstrate,
       "a part already on the table (--substrate): it stands on the plate, is not deposited, and the head keeps clear of it", {}},
      {kRegionOnSubstrate,
       "the part less the substrate (--substrate), deposited onto the substrate along the given direction; its first beads rest on the "
       "substrate's surface",
       {}},
      {kRegionTrunk, "the part's trunk, split off along its skeleton from the branches that grow out of its side, built first as one region",
       {}},
      {kRegionOnTrunk,
       "a branch that leaves its trunk sideways (the part along its skeleton, the trunk being the part within the tubes around the "
       "other skeleton edges): built after the trunk along the trunk's outward normal under its base, its first beads on the trunk's "
       "curved surface, where a plane cut would leave its start hanging",
       {{"tube_sides", detail::kTubeSides}, {"tube_margin_beads", detail::kTubeMarginBeads}}},
      {kDirectionRedirected,
       "a region is built along another direction than the decomposition gave it: along that one the head struck earlier deposit, the "
       "plate or the table where no build order or torch tilt cleared it; tried in turn, its base's normal, half-way to it, its parent's "
       "direction and half-way to that, and kept the one whose program reads back clean with the least overhang",
       {{"redirect_min_deg", kRedirectMinDeg}}},
      {kLayersAsked, "the region's layers are those --layers asked for (planar, tilted or conformal)", {}},
      {kLayersPlanar,
       "the region keeps planar layers: they leave no overhang, or tilted and conformal layers leave no less than half of it, cannot "
       "follow the part, or the plan on them reads back worse",
       {{"tilted_gain_share", kTiltedGainShare}}},
      {kLayersTilted,
       "the region takes tilted \"3-D\" layers along its centroidal axis (Ruan §4.2.2): its planar layers overhang and the tilted ones "
       "leave less than this share of it, each thickness in the process's range and the volumetric difference of adjacent layers within "
       "voldiff (Eq. 9)",
       {{"tilted_gain_share", kTiltedGainShare},
        {"voldiff", process.voldiff},
        {"layer_min_mm", process.layer_min_mm},
        {"layer_max_mm", process.layer_max_mm}}},
      {kLayersConformal,
       "the region takes conformal layers: level sets of the distance from the prebuilt part's surface at an even step, the torch along "
       "the distance's gradient (Kapil's offset surfaces); its planar layers overhang and the conformal ones, compared on their footprints "
       "down the gradient, leave less than this share of it, and less than tilted ones",
       {{"tilted_gain_share", kTiltedGainShare},
        {"layer_min_mm", process.layer_min_mm},
        {"layer_max_mm", process.layer_max_mm},
        {"field_tolerance_mm", slicing::kFieldToleranceMm}}},
      {kRuleStart, "the root region's first layer starts the build, on the plate", {}},
      {kRuleFather, "a child region starts once its father is complete (Dwivedi: a child is not built before its father)", {}},
      {kRuleContinue, "the region being built goes on with its next layer (Dwivedi Rule 4: layers of a region in layer order)", {}},
      {kRuleLevel,
       "layers of brother regions whose C-space contours (the contour grown by the head's radius, Dwivedi Eq. 3) overlap share an "
       "interference level (Rule 2); the lowest pending level is built first, in region order (Rule 3), so brothers are built level by "
       "level",
       {{"c_space_radius_mm", plan.c_space_radius_mm},
        {"c_space_margin_mm", process.rules.c_space_margin_mm},
        {"interleave", process.rules.interleave ? 1.0 : 0.0}}},
      {kReorientRegion, "the tool axis turns to the next region's direction before its layer", {{"reorientation_deg", kReorientationDeg}}},
      {kReorientLayer, "the tool axis turns between two layers of a region where their tilts differ", {{"reorientation_deg", kReorientationDeg}}},
      {kReorientTilt, "the tool axis turns along a layer where the torch tilt changes", {{"reorientation_deg", kReorientationDeg}}},
      {kTiltNormal, "the torch stays along the layer's normal: nothing overhangs", {}},
      {kTiltOverhang,
       "the torch tilts over overhanging surface contours, outer and hole (Kapil Eq. 3), smoothed within the tilt axis's speed",
       {{"self_supporting_deg", alpha}, {"max_step_bead_share", process.max_step_bead_share}}},
      {kTiltClearance,
       "tool axes are turned towards the table's normal where the head would come too close to the plate or the table, or leave the "
       "tilt axis's reach",
       {{"reach_deg", reach_deg}, {"nozzle_cylinder_radius_mm", machine.nozzle.cylinder_radius_mm}}},
      {kTiltOnPlate, "layers laid on the plate are deposited with the torch upright", {}},
      {kTiltEased,
       "where the head would strike the deposit laid before, the torch turns towards the layer's normal, then towards the table's "
       "(a quarter at a time, within the torch's tilt limit) as far as it must, keeping the plate, the table and the reach clear",
       {{"deposit_margin_mm", detail::kDepositMarginBeads * process.bead_width_mm}}},
      {"travel.clear",
       "moves between layers and regions go straight where the head clears the plate, the table and the deposit; else out along both "
       "tool axes and across; else over a sphere around the part",
       {{"deposit_margin_mm", detail::kDepositMarginBeads * process.bead_width_mm}}},
  };
}

}  // namespace polyaxis::planner
