// The whole job as one library call (SPEC §1): from a repaired part, a machine and a process to a
// verified machine program. The CLI's `plan` is a thin shell over it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/analysis/decompose.h"
#include "polyaxis/core/progress.h"
#include "polyaxis/core/result.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/verify/simulate.h"
#include "polyaxis/verify/verify.h"
#include "polyaxis/planner/plan.h"

namespace polyaxis::planner {

// The default work budget of one decomposition in plan_part, in facet visits.
inline constexpr double kDefaultDecomposeBudget = 3e8;

enum class Strategy {
  kSingle,     // one region along `direction`
  kDecompose,  // analysis::decompose's regions, each along its own direction
  kAuto,       // both; keeps the better (PlanPartOptions)
};

struct PlanPartOptions {
  Strategy strategy = Strategy::kAuto;
  Vec3 direction{0, 0, 1};       // the single region's build direction, and the root's default
  analysis::RootBase root_base;  // where the root region stands (decompose; auto tries kLowest too)
  PlanOptions plan;              // perimeters, tilt, retract, threads (plan.direction is set from `direction`)
  post::GcodeOptions gcode;   // path tolerance
  // Work each decomposition may do (analysis::DecomposeOptions::work_budget_facet_visits): a few
  // seconds on one core; 0 for no limit. Splitting stops there with the regions found so far.
  double decompose_budget_facet_visits = kDefaultDecomposeBudget;
  // A program that, read back, still strikes the plate, the table or earlier deposit is an error
  // (kInfeasible) unless this is set (`--allow-collisions`): then it is kept, with a warning.
  bool allow_collisions = false;
  // A decomposition whose program strikes something no build order or torch tilt clears has the
  // regions struck built along other directions (the rule kDirectionRedirected, docs/plan.md)
  // before the plan is given up; false (`--keep-directions`) keeps every region along the
  // decomposition's direction.
  bool redirect_regions = true;
  // A part already on the table (`--substrate MESH`, in the part's frame): the part less it is
  // deposited onto it, along `direction` (kSingle) or each connected piece along the substrate's
  // normal under its base (kDecompose), kAuto choosing as docs/plan.md says; it stands on the
  // plate. The head keeps clear of it (verify.h).
  std::optional<mesh::Mesh> substrate;
  // Regions of the decomposition already made (`--prebuilt ID`): the root, or regions whose parent
  // is prebuilt; they stand on the table and the rest is deposited onto them (the strategy must
  // not be kSingle).
  std::vector<std::uint32_t> prebuilt;
  // The call's stages go here instead of stderr (core/progress.h); options.plan.threads bounds its
  // worker threads (0: all cores), for this call only.
  core::ProgressCallback progress;
};

struct PlanPartResult {
  Plan plan;
  std::string gcode;
  verify::SimulationReport simulation;  // the program read back and compared with the plan
  verify::BuildCheck check;             // the program checked against the build model
  std::optional<analysis::CentroidalAxis> axis;  // the decomposition's, when it was used
  Strategy strategy_used = Strategy::kSingle;
  std::string choice;                    // what was chosen and why, one sentence
  std::vector<std::string> warnings;     // not support-free regions, thin regions, ...
  // choose_s: all of plan_part but the kept program's G-code, simulation and verification: choosing
  // the plan (every candidate tried: directions, decompositions, layers; the programs of choices
  // dropped after their read-back; relief rounds), which includes the chosen plan's own stages
  // (Plan::times).
  double choose_s = 0.0, gcode_s = 0.0, simulate_s = 0.0, verify_s = 0.0;
  post::GcodeStats gcode_stats;         // blocks the machine's axis limits slowed
};

// Plans PART on MACHINE with PROCESS.
// - kSingle: make_plan along options.direction.
// - kDecompose: the part's centroidal axis and region tree (analysis::decompose, rooted at
//   options.root_base), then make_plan over the regions.
// - kAuto: kSingle; when that is not support-free, kDecompose too (rooted at options.root_base,
//   then at the lowest point when that root leaves a region below the plate or out of reach); when
//   the part has a ceiling along the direction (faces turned down, which no torch tilt holds), the
//   two are made side by side, with the same result as one after the other. Keeps
//   the plan with the least unsupported area; on a tie the fewer regions, then the fewer
//   reorientations. A candidate that fails is skipped when the other succeeds.
// Then the G-code, its simulation against the plan and its verification against the build model.
// With kAuto, a decomposition whose program cannot be written (a limit only the program shows,
// such as C winding past its end stops), or, read back, starts a region in mid-air or still
// collides, gives way to the single direction when that one reads back clean.
// Layers (options.plan.layers, PlanOptions): with kAuto each region takes tilted layers where its
// planar ones overhang and the tilted ones leave less (make_plan); a plan that took tilted layers
// anywhere is then compared with the whole choice made on planar layers, and the one that reads
// back clean, then by the order above, is kept (a tilted plan that cannot be written or reads back
// colliding gives way to the planar one). choice and the regions' layers_why say which and why.
// Errors: those of make_plan and write_gcode (kUsage naming options, kInfeasible, kMachineLimit
// naming the region, direction and limit); a program breaking a machine limit is kMachineLimit; a
// program with collisions is kInfeasible naming the first ones (unless allow_collisions).
core::Result<PlanPartResult> plan_part(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                       const process::ProcessConfig& process, const PlanPartOptions& options = {});

// "single", "decompose", "auto".
const char* strategy_name(Strategy s);

// An area in mm² for messages, with enough digits that a non-zero one never reads 0.0 ("0.011").
std::string area_text(double mm2);

}  // namespace polyaxis::planner
