// The planner's own collision avoidance against the deposit (issue 12, items 2–3), before any
// G-code exists (verify/deposit_check.h); the read-back verification still judges the result.
// Private to the planner.
#pragma once

#include <cstddef>
#include <vector>

#include "polyaxis/planner/plan.h"
#include "polyaxis/verify/deposit_check.h"
#include "transit.h"

namespace polyaxis::planner::detail {

// Clearance the planner keeps from the deposit beyond the verification's own (mm, a share of the bead).
inline constexpr double kDepositMarginBeads = 0.5;

// The path points of PLAN's toolpaths in build order (empty paths skipped), as the program visits them.
std::vector<verify::PlannedPoint> planned_points(const Plan& plan);

// Where the torch at a deposit point would strike the deposit laid before it (tilted, or of a
// region other than the root), the axis is turned towards the layer's normal (a quarter, a half,
// three quarters, all of the way), then towards the table's (within toolpath::kMaxTiltRad), keeping
// the plate, the table and the reach clear (guard_axis); the first that clears, with the move into
// the point from the path's point before it, is kept. The move into a point along the normal from
// a tilted one is checked too (the head turning back), and where the point cannot turn, the point
// before turns towards the normal. A deposit move whose joints would hold the tip below the
// writer's share of DEPOSIT_FEED_MM_S (post::splits_stall) is turned in place by the G-code writer
// (post/gcode.h, stall split), and checked so; every other move is checked turning as it goes. On
// the other posts (machine.post), which split by rules of their own, a deposit move is checked
// both ways. Counts go to the layers' toolpaths (axes_eased) and the plan (tilts_eased).
void ease_tilts(Plan& plan, const machine::MachineConfig& machine, const PlanOptions& options, const verify::DepositCheck& deposit,
                double bead_mm, double deposit_feed_mm_s);

// The nozzle's radius: the wider of the cone's top and the cylinder (mm).
double nozzle_radius_mm(const machine::NozzleModel& nozzle);

// True when some vertex of a region other than LAYER's own lies above LAYER's plane within REACH_MM
// of its section (bounding circle): only there can a head along the layer's normal strike deposit.
bool others_above(const Plan& plan, std::size_t layer, double reach_mm);

// Travel from FROM (axis A) to TO (axis B), both retracted from the part, that keeps the head clear
// of the plate, the table and the deposit laid before program point BEFORE: straight when that is
// clear, else out along both axes by growing distances and across, else over the sphere
// (CENTRE, RADIUS) (transit.h). Returns the points strictly between FROM and TO.
std::vector<TransitPoint> clear_travel(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before,
                                       double clearance_mm, double margin_mm, Vec3 from, Vec3 a, Vec3 to, Vec3 b, Vec3 centre,
                                       double radius);

// The travel between two paths of a layer, from the deposit point FROM (axis A) to TO (axis B):
// straight (none returned) where its samples between the ends keep clear of the deposit laid before
// program point BEFORE and out of the plate and the table; else out along both axes by growing
// distances and across, each leg CLEARANCE_MM clear of the plate and the table; straight again when
// no lift clears (the read-back verification judges it).
std::vector<TransitPoint> layer_travel(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before,
                                       double clearance_mm, double margin_mm, Vec3 from, Vec3 a, Vec3 to, Vec3 b);

}  // namespace polyaxis::planner::detail
