// The physical build model (SPEC §2.6, Dwivedi Eq. 2): the machine table, the substrate plate the
// part grows from, and the head (nozzle cone, cylinder, optional boxes), in the table frame of a
// placed part: +Z is the table's normal, the substrate's top is Z = 0 and the part stands on it.
// The material deposited so far is the program itself (verify/verify.h keeps it while reading).
//
// Clearance is conservative: the head's solids are bounded by circles about the nozzle axis
// (the cone and the cylinder exactly, since their lowest points lie on their end circles; each
// head box by the solid it sweeps turning about the axis), and a circle counts against the
// substrate whenever its bounding disc overlaps the plate's rectangle, else against the table.
#pragma once

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

struct BuildModel {
  NozzleModel nozzle;
  std::vector<HeadBox> head_boxes;
  double table_radius_mm = 250.0;
  Vec3 table_centre_mm;  // where the C axis crosses the table (x, y of the rotation point)
  SubstratePlate substrate;

  double table_top_z_mm() const { return substrate.top_z_mm - substrate.thickness_mm; }
};

// The model for MACHINE and PROCESS with a part whose footprint (table frame, after placement)
// spans [X0, X1] × [Y0, Y1]: the plate is process.substrate's size centred on the footprint, or the
// footprint grown by its margin.
BuildModel make_build_model(const MachineConfig& machine, const process::ProcessConfig& process, double x0_mm, double y0_mm, double x1_mm,
                            double y1_mm);

// The head's clearance with its tip at TIP and its axis (tip → up the nozzle, any length > 0)
// along AXIS, both in the table frame: the least height of any head point above the surface under
// it (substrate top over the plate, table top elsewhere), the tip itself left out. Negative: the
// head enters the plate or the table by that much. +inf when nothing is under the head.
// Cost: constant (a few circles per head part).
double head_clearance_mm(const BuildModel& model, Vec3 tip, Vec3 axis);

// The tip's own height above the surface under it (negative: below the substrate or table top).
double tip_clearance_mm(const BuildModel& model, Vec3 tip);

}  // namespace polyaxis::machine
