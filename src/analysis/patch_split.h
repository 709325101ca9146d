// Splits for the overhang that the centroidal axis's links leave (SPEC §2.3: a region that is not
// support-free is split further). Private to the analysis module (decompose.cpp).
#pragma once

#include <vector>

#include "region_geometry.h"
#include "split_screen.h"

namespace polyaxis::analysis::detail {

// Facet visits the screening of one patch's candidates is aimed at (fewer candidates on large meshes).
inline constexpr double kPatchScreenBudget = 2e7;

struct PatchCandidate {
  Vec3 point, normal;  // the plane; normal towards the child, which holds the patch
  Screened screened;
};

// Candidate planes that cut the overhang patch PATCH of HOST off into a child of its own, screened
// (screen_split), only those whose child is support-free, best first (least overhang left, then the smallest child, then the child
// built nearest to the host's direction). The planes' normals are directions of a Fibonacci sphere along which the patch
// itself stands (no facet of it past α − a margin); each plane lies just below the patch along its
// normal, or stepped back by fractions and multiples of STEP_MM. A child may not take the host's
// base. Screening is parallel; the candidate count is capped at kMaxPatchCandidates and so that a
// patch costs about kPatchScreenBudget facet visits (fewer directions on large meshes), the
// directions thinned evenly. Deterministic.
std::vector<PatchCandidate> patch_candidates(const HostRegion& host, const OverhangPatch& patch, double step_mm, double alpha_deg);

// Up to kMaxTargets points standing for PATCH (centroids of its largest facets): the exact cut keeps
// as the child the shell nearest to them.
std::vector<Vec3> patch_targets(const mesh::Mesh& m, const OverhangPatch& patch);

}  // namespace polyaxis::analysis::detail
