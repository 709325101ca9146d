// A part split into a trunk and the branches that grow out of its side, along the part's skeleton:
// the trunk is built first, and each branch on conformal layers from the trunk's surface (Kapil's
// features on a prebuilt hub, with the hub deposited first). A branch that leaves its trunk
// sideways hangs over it where it starts; no plane cut can give it a base there, the trunk's
// curved surface can. Private to the planner module.
#pragma once

#include <string>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/repair.h"

namespace polyaxis::planner::detail {

// The tube around the trunk's axis is the ball inscribed in the part there, centred, its radius
// divided by cos(π / kTubeSides) (a tube of kTubeSides faces holds the ball) and grown by
// kTubeMarginBeads bead widths: it holds the round limb the axis runs through and its tessellation,
// and the branch leaving it keeps all but that thin band (narrower than the layer below is grown
// by the support check, t·tan α at the least layer) of where it starts.
inline constexpr int kTubeSides = 32;
inline constexpr double kTubeMarginBeads = 0.1;
// At a free end the tube runs on past the skeleton's last ball by this many radii, so that it holds
// a flat end's rim.
inline constexpr double kTubeEndRadii = 1.5;
// The skeleton's voxel chain is smoothed over this many points either side and resampled every
// kStepVoxels voxels before it is centred.
inline constexpr int kSmoothVoxels = 2;
inline constexpr double kStepVoxels = 1.5;
// A point of a tube's axis is centred by the limb's side: where the nearest surface's normal is
// within acos(kAcrossCos) of the axis, it is an end face, and the point is left out.
inline constexpr double kAcrossCos = 0.5;
// The trunk's axis leaves out the points within this many radii (plus a voxel) of a branch point's
// inscribed ball centre, where the junction's bulge pulls the skeleton off the limb's axis.
inline constexpr double kJointRadii = 1.25;
// A trunk is split off only along round limbs: of kRoundSamples points round the tube at each
// centred axis point, at least kRoundHugShare lie within kRoundShare of the radius (and the margin)
// of the part's surface.
inline constexpr int kRoundSamples = 16;
inline constexpr double kRoundShare = 0.15;
inline constexpr double kRoundHugShare = 0.8;
// The run past a free end bends no tighter than this many tube radii.
inline constexpr double kLeastBendRadii = 2.0;
// Branch points at most tried, nearest the skeleton's root first (two splits at each).
inline constexpr std::size_t kMaxTrunkSplits = 2;

struct TrunkSplit {
  mesh::Mesh trunk;   // the part within the trunk's tubes: closed, built first
  mesh::Mesh rest;    // the part less the tubes: the branches, closed
  // The tubes' union: where they cut the part, the branches' base; smooth (the trunk's own surface
  // has a step of the margin where the tubes leave the limbs), so the distance from it, whose levels
  // are the branches' conformal layers, bends only where the tubes do.
  mesh::Mesh tubes;
  std::string label;  // "the branch leaving (x, y, z)", "the 3 branches leaving (x, y, z)"
  std::string refused;  // why this split could not be made (the meshes then empty); empty when made
};

// The splits of PART (repaired, one solid) at its skeleton's branch points: at each, the child
// edge that turns least from the edge into it continues the trunk, and the other children with all
// that grows from them are the branches, and then all of them, the trunk ending there; the trunk
// is the part within the tubes around the other edges. A branch point none of whose side children
// is a round limb (a spur of the skeleton in a flat foot) is passed over. A trunk chain that cannot be tubed (a foot's or a flange's flat disc is not round) is left out;
// then only the sides leaving a tubed chain stay branches, and the pieces of the part outside the
// tubes that hold none of their skeleton (the foot) go back to the trunk.
// BEAD_MM sizes the tubes' margin. A split where no branch leaves a tubed chain, whose tubes cross
// themselves, or where the boolean operations fail or leave either side empty, says so in
// `refused`. At most kMaxTrunkSplits branch points, two splits each.
std::vector<TrunkSplit> trunk_splits(const mesh::RepairedMesh& part, double bead_mm);

}  // namespace polyaxis::planner::detail
