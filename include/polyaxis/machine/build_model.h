// The physical build model (SPEC §2.6, Dwivedi Eq. 2): the machine table, the substrate plate the
// part grows from, and the head (nozzle cone, cylinder, optional boxes), in the table frame of a
// placed part: +Z is the table's normal, the substrate's top is Z = 0 and the part stands on it.
// The material deposited so far is the program itself (verify/verify.h keeps it while reading).
//
// Each solid of the head is the hull of two discs about the nozzle axis: the cone from 1 mm above
// the tip (below that it is the tip's own clearance), the cylinder, and each head box by the solid
// it sweeps turning about the axis. Against the plate the clearance is exact (the lowest point of
// a solid's part over the plate's rectangle); against the table it is conservative (a solid's
// lowest point, wherever one of its discs overlaps the table).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::machine {

using core::Vec3;

struct SubstratePlate {
  double x_min_mm = 0.0, y_min_mm = 0.0, x_max_mm = 0.0, y_max_mm = 0.0;  // its rectangle, table frame
  double top_z_mm = 0.0;       // the part's base
  double thickness_mm = 10.0;  // the table's top is top_z_mm − thickness_mm
};

// A part already on the table (`plan --substrate`, `--prebuilt`): the deposit is laid onto it and
// the head keeps clear of it. Its surface is kept as points at most spacing_mm apart with their
// outward normals (table frame): verify_build and DepositCheck treat them as material laid before
// the whole program (the head against balls set half their radius inside the surface, so the
// check is conservative by half a ball), and a bead rests on it as on earlier deposit.
// Surface points of a prebuilt body at most this share of the bead apart: every surface point is
// within 0.4 / √3 = 0.23 bead of one, and a ball of the deposit's radius (0.56 bead) set half its
// radius inside the surface covers 0.48 bead of it around its point.
inline constexpr double kPrebuiltSpacingBeads = 0.4;

struct PrebuiltBody {
  std::vector<Vec3> surface_mm;
  std::vector<Vec3> normals;
  double spacing_mm = 0.0;
  bool empty() const { return surface_mm.empty(); }
};

struct BuildModel {
  NozzleModel nozzle;
  std::vector<HeadBox> head_boxes;
  double table_radius_mm = 250.0;
  Vec3 table_centre_mm;  // where the C axis crosses the table (x, y of the rotation point); the middle of the travel on a fixed table
  SubstratePlate substrate;
  PrebuiltBody prebuilt;

  double table_top_z_mm() const { return substrate.top_z_mm - substrate.thickness_mm; }
};

// The model for MACHINE and PROCESS with a part whose footprint on the plate (table frame, after
// placement: what stands on the plate, not the part's whole shadow) spans [X0, X1] × [Y0, Y1]: the
// plate is process.substrate's size centred on the footprint, or the footprint grown by its margin.
BuildModel make_build_model(const MachineConfig& machine, const process::ProcessConfig& process, double x0_mm, double y0_mm, double x1_mm,
                            double y1_mm);

// The surface of the closed mesh (VERTICES, TRIANGLES counter-clockwise from outside, table
// frame) sampled at most SPACING_MM apart: the corners of its triangles, each split at its longest
// edge's middle until no edge is longer than that, each with its face's outward normal (a point
// of the surface is within SPACING_MM / √3 of a sample; corners shared by faces are sampled by
// each). Appended to BODY; nothing for a spacing that is not finite and positive, and faces with
// non-finite corners are skipped. False, with BODY as it was, when that takes more than
// MAX_SAMPLES samples (a surface too large for the spacing: a real one stays far below).
// Cost: linear in the surface area / spacing² plus the edges' length / spacing, bounded by MAX_SAMPLES.
inline constexpr std::size_t kMaxPrebuiltSamples = 4'000'000;  // 192 MB; the impeller's hub at 0.36 mm: about 0.2e6
[[nodiscard]] bool add_prebuilt(PrebuiltBody& body, const std::vector<Vec3>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                double spacing_mm, std::size_t max_samples = kMaxPrebuiltSamples);

// The head's clearance with its tip at TIP and its axis (tip → up the nozzle, any length > 0)
// along AXIS, both in the table frame: the least height of any head point above the surface under
// it (substrate top over the plate, table top elsewhere), the first millimetre above the tip left
// out. Negative: the head enters the plate or the table by that much. +inf when nothing is under
// the head. A clearance of EXACT_BELOW_MM or more may be reported as a lower bound of at least
// EXACT_BELOW_MM (for callers that compare with it). Cost: constant; a few discs per solid, and
// where a solid crosses the plate's edge its sides and corners (closed form).
double head_clearance_mm(const BuildModel& model, Vec3 tip, Vec3 axis, double exact_below_mm = std::numeric_limits<double>::infinity());

// The tip's own height above the surface under it (negative: below the substrate or table top).
double tip_clearance_mm(const BuildModel& model, Vec3 tip);

}  // namespace polyaxis::machine
