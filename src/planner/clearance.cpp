#include "clearance.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "polyaxis/post/gcode.h"
#include "reach.h"

namespace polyaxis::planner::detail {
namespace {

// Travel is checked at most this far apart (mm) and this much axis turn apart (degrees).
constexpr double kTravelStepMm = 1.0;
constexpr double kTravelStepDeg = 2.0;
// Distances tried out along the axes before crossing (mm), before the sphere.
constexpr double kLiftsMm[] = {10.0, 25.0, 50.0, 100.0};
// A move turning the axis by more than this (degrees) is not checked as one: the transit takes it.
constexpr double kMaxMoveTurnDeg = 120.0;
// A transit's leg out of or into a tip turns its axis up in steps of this (degrees) until clear.
constexpr double kLegRaiseStepDeg = 5.0;
constexpr double kPi = 3.14159265358979323846;
// A move this short, turning this little, is cleared by one check with its length and turn as the
// margin (a wider one would visit most of the deposit).
constexpr double kBroadCheckMm = 5.0;
constexpr double kBroadCheckRad = 5.0 * kPi / 180.0;

bool clear_at(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before, double clearance_mm,
              double margin_mm, Vec3 tip, Vec3 axis) {
  return machine::head_clearance_mm(model, tip, axis, clearance_mm) >= clearance_mm && !deposit.strikes(tip, axis, before, margin_mm);
}

// The angle between two axes (any length > 0), radians.
double turn_rad(Vec3 a, Vec3 b) { return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)); }

// True when CLEAR holds at the samples K = FIRST … PIECES − 1 + LAST_TOO of the move from (P, A)
// to (Q, B) in PIECES steps at most kTravelStepMm and kTravelStepDeg apart: the tip straight, the
// axis along the great circle evenly in angle with the same fraction, as the post writes the move
// (axis_between; an even fraction of the chord instead ran behind the program's axis, and a head
// pointing below the horizon was checked up to 0.7 mm higher over the table than the program put
// it). False for a turn of more than kMaxMoveTurnDeg: such a move goes over the sphere instead.
template <typename Clear>
bool clear_samples(Vec3 p, Vec3 a, Vec3 q, Vec3 b, int first, bool last_too, Clear clear) {
  const double turn = turn_rad(a, b) * 180.0 / kPi;
  if (turn > kMaxMoveTurnDeg) return false;
  const int pieces = std::max(1, static_cast<int>(std::ceil(std::max(core::norm(q - p) / kTravelStepMm, turn / kTravelStepDeg))));
  for (int k = first; k < pieces + (last_too ? 1 : 0); ++k) {
    const double u = static_cast<double>(k) / pieces;
    if (!clear(p + (q - p) * u, axis_between(a, b, u))) return false;
  }
  return true;
}

// The samples of the move from (P, A) to (Q, B) strictly between its ends against the deposit only.
bool clear_move_deposit(const verify::DepositCheck& deposit, std::size_t before, double margin_mm, Vec3 p, Vec3 a, Vec3 q, Vec3 b) {
  return clear_samples(p, a, q, b, 1, false, [&](Vec3 tip, Vec3 axis) { return !deposit.strikes(tip, axis, before, margin_mm); });
}

// The axis a turn in place passes through on a table-tilt machine: tilt from the table's normal
// and azimuth about it each linear (one G-code block, joints interpolated), the azimuth the short
// way round; at the pole the azimuth of the other end.
Vec3 joint_lerp(Vec3 a, Vec3 b, double u) {
  a = core::normalized(a), b = core::normalized(b);
  const double ta = std::acos(std::clamp(a.z, -1.0, 1.0));
  const double tb = std::acos(std::clamp(b.z, -1.0, 1.0));
  double pa = std::atan2(a.y, a.x), pb = std::atan2(b.y, b.x);
  if (std::hypot(a.x, a.y) < 1e-9) pa = pb;
  if (std::hypot(b.x, b.y) < 1e-9) pb = pa;
  double dp = std::remainder(pb - pa, 2.0 * kPi);
  const double t = ta + (tb - ta) * u, phi = pa + dp * u;
  return {std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)};
}

// The turn in place at P from axis A to B, as joints interpolate it, against the deposit only: its
// end (P, B) too, where the bead then starts (the point before, (P, A), is checked as a point).
bool clear_turn_deposit(const verify::DepositCheck& deposit, std::size_t before, double margin_mm, Vec3 p, Vec3 a, Vec3 b) {
  const int pieces = std::max(1, static_cast<int>(std::ceil(turn_rad(a, b) * 180.0 / kPi / kTravelStepDeg)) * 2);
  for (int k = 1; k <= pieces; ++k) {
    if (deposit.strikes(p, joint_lerp(a, b, static_cast<double>(k) / pieces), before, margin_mm)) return false;
  }
  return true;
}

// Every sample of the move from (P, A) to (Q, B), both ends included, against the plate, the table
// and the deposit.
bool clear_move(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before, double clearance_mm,
                double margin_mm, Vec3 p, Vec3 a, Vec3 q, Vec3 b) {
  return clear_samples(p, a, q, b, 0, true, [&](Vec3 tip, Vec3 axis) { return clear_at(model, deposit, before, clearance_mm, margin_mm, tip, axis); });
}

}  // namespace

double nozzle_radius_mm(const machine::NozzleModel& nozzle) {
  return std::max(nozzle.cylinder_radius_mm, nozzle.cone_height_mm * std::tan(nozzle.tip_half_angle_deg * kPi / 180.0));
}

bool others_above(const Plan& plan, std::size_t layer, double reach_mm) {
  const slicing::Layer& l = plan.layers.layers[layer];
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  for (const geom2d::Polygon& poly : l.polygons) {
    for (const geom2d::Point& q : poly.outer) {
      const double u = geom2d::to_mm(q.x), v = geom2d::to_mm(q.y);
      u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v);
    }
  }
  if (u0 > u1) return false;
  const Vec3 centre = l.frame.to_world(0.5 * (u0 + u1), 0.5 * (v0 + v1));
  const double radius = 0.5 * std::hypot(u1 - u0, v1 - v0) + reach_mm;
  for (const PlanRegion& r : plan.placed_regions) {
    if (r.id == plan.region_of_layer[layer]) continue;
    for (const Vec3& v : r.mesh.vertices) {
      const Vec3 d = v - centre;
      const double h = core::dot(d, l.frame.d);
      if (h > 0.0 && core::norm(d - l.frame.d * h) <= radius) return true;
    }
  }
  return false;
}

std::vector<verify::PlannedPoint> planned_points(const Plan& plan) {
  std::vector<verify::PlannedPoint> out;
  for (const toolpath::LayerToolpaths& lt : plan.toolpaths) {
    for (const toolpath::Path& path : lt.paths) {
      for (const toolpath::PathPoint& p : path.points) out.push_back({p.position_mm, p.deposit});
    }
  }
  return out;
}

void ease_tilts(Plan& plan, const machine::MachineConfig& machine, const PlanOptions& options, const verify::DepositCheck& deposit,
                double bead_mm, double deposit_feed_mm_s) {
  const double reach = reach_rad(machine), margin = kDepositMarginBeads * bead_mm;
  const double tilted_cos = std::cos(kTiltedDeg * kPi / 180.0);
  const std::uint32_t root = plan.placed_regions.empty() ? 0 : plan.placed_regions.front().id;
  const double head_reach = nozzle_radius_mm(plan.build_model.nozzle);
  // Where the program turns the torch in place is known for the LinuxCNC post (post::splits_stall).
  const bool writer_rule = machine.post == machine::PostDialect::kLinuxCnc;
  // The deposit a point is checked against is the tips laid before it, which no easing moves, and
  // a move into a point depends on its layer's point before only: the layers are eased side by
  // side. FIRST: each layer's first point in the flat order.
  std::vector<std::size_t> first(plan.toolpaths.size() + 1, 0);
  std::uint64_t eased_before = 0;
  for (const toolpath::LayerToolpaths& lt : plan.toolpaths) eased_before += lt.axes_eased;
  for (std::size_t k = 0; k < plan.toolpaths.size(); ++k) {
    first[k + 1] = first[k];
    for (const toolpath::Path& path : plan.toolpaths[k].paths) first[k + 1] += path.points.size();
  }
  tbb::parallel_for(std::size_t{0}, plan.toolpaths.size(), [&](std::size_t k) {
    const Vec3 n = plan.layers.layers[k].frame.d;
    toolpath::PathPoint* previous = nullptr;  // the layer's point before, across its paths
    toolpath::PathPoint* previous2 = nullptr;  // and the one before that
    const bool exposed = plan.region_of_layer[k] != root && others_above(plan, k, head_reach);
    auto is_tilted = [&](const toolpath::PathPoint& q) { return core::dot(core::normalized(q.tool_axis), n) < tilted_cos; };
    // The point I at TIP with AXIS, and the move into it from BEFORE (its axis FROM_AXIS; none for
    // a layer's first point; LAID: the move deposits), against the deposit: the axis turning on the
    // way, or, where the rotary axes cannot keep up (the G-code writer's stall split), turned in
    // place first and held along the move, which also keeps clear of the plate and the table.
    auto strikes_at = [&](std::size_t i, Vec3 tip, Vec3 axis, bool laid, const toolpath::PathPoint* before, Vec3 from_axis) {
      // Over the move no head point comes nearer than the move's length plus the turn times its
      // distance from the tip: clear with that margin, the move is clear, and the point with it
      // (the wider check holds the narrower one: one search where most points are clear).
      const Vec3 from = before != nullptr ? before->position_mm : tip;
      const double turn = before != nullptr ? turn_rad(from_axis, axis) : 0.0;
      const double length = core::norm(tip - from);
      const bool broad = before != nullptr && length <= kBroadCheckMm && turn <= kBroadCheckRad;
      if (broad && !deposit.strikes(tip, axis, i, margin + length, turn)) return false;
      if (deposit.strikes(tip, axis, i, margin)) return true;
      if (before == nullptr) return false;
      if (turn < 1e-6) return !clear_move_deposit(deposit, i, margin, from, axis, tip, axis);
      // The plate and the table, which each end's guard kept clear at its own tip only, and the
      // deposit, on the way the program goes: where the writer's joints cannot keep the tip at the
      // deposit feed it turns the torch in place with the process off, then lays the bead with the
      // new axis (post::splits_stall, the writer's own rule; its turn in place is the axis along
      // the great circle, or the joints' interpolation in one block: both are checked, and the
      // turn's end, where the bead starts); elsewhere the tip moves and the axis turns together.
      // The other posts split by rules of their own: there a deposit move is checked both ways.
      const machine::BuildModel& model = plan.build_model;
      const double clearance = options.head_clearance_mm;
      const bool in_place = laid && (!writer_rule || post::splits_stall(machine, from, from_axis, tip, axis, deposit_feed_mm_s));
      if (in_place &&
          (!move_clear(model, clearance, from, from_axis, from, axis) || !move_clear(model, clearance, from, axis, tip, axis) ||
           !clear_move_deposit(deposit, i, margin, from, from_axis, from, axis) || !clear_turn_deposit(deposit, i, margin, from, from_axis, axis) ||
           !clear_move_deposit(deposit, i, margin, from, axis, tip, axis))) {
        return true;
      }
      if (in_place && writer_rule) return false;
      return !move_clear(model, clearance, from, from_axis, tip, axis) || !clear_move_deposit(deposit, i, margin, from, from_axis, tip, axis);
    };
    // AXIS turned up where the plate, the table or the reach need it (guard_axis); false where no turn does.
    auto guarded = [&](Vec3 tip, Vec3& axis) {
      return guard_axis(machine, plan.build_model, reach, options.head_clearance_mm, options.retract_mm, tip, n, axis);
    };
    std::size_t flat = first[k];
    std::vector<toolpath::Path>& paths = plan.toolpaths[k].paths;
    for (std::size_t j = 0; j < paths.size(); ++j) {
      toolpath::Path& path = paths[j];
      // A travel's ends take the axes of the points it joins (below); the move into a path after a
      // travel is the travel, which the program routes clear of what is built (layer_travel) with
      // the axis it turns through: the path's first point is checked alone.
      const bool after_travel = j > 0 && paths[j - 1].kind == toolpath::PathKind::kTravel;
      for (std::size_t m = 0; m < path.points.size(); ++m) {
        toolpath::PathPoint& p = path.points[m];
        const std::size_t i = flat++;
        toolpath::PathPoint* before = m == 0 && after_travel ? nullptr : previous;
        toolpath::PathPoint* before2 = m == 0 && after_travel ? nullptr : previous2;
        previous2 = previous, previous = &p;
        if (path.kind == toolpath::PathKind::kTravel) continue;
        auto strikes = [&](Vec3 axis) { return strikes_at(i, p.position_mm, axis, p.deposit, before, before ? before->tool_axis : axis); };
        // Along the layer's normal a planar layer's head stays above everything its own region
        // laid before: only other regions' deposit above the layer's plane can be struck there, or
        // the head turning back from a tilt on the move into the point (a travel between paths is
        // routed around by the program instead: make_program).
        const bool tilted = is_tilted(p);
        const bool turning_back = before != nullptr && path.kind != toolpath::PathKind::kTravel && is_tilted(*before);
        if ((!tilted && !exposed && !turning_back) || !strikes(p.tool_axis)) continue;
        // Towards the layer's normal first, then towards the table's (within the torch's tilt limit).
        std::vector<Vec3> candidates;
        for (const double f : {0.25, 0.5, 0.75, 1.0}) {
          if (tilted) candidates.push_back(core::normalized(p.tool_axis * (1.0 - f) + n * f));
        }
        for (const double f : {0.25, 0.5, 0.75, 1.0}) {
          const Vec3 up = core::normalized(p.tool_axis * (1.0 - f) + Vec3{0, 0, 1} * f);
          if (core::norm(up) > 0.5 && core::dot(up, n) >= std::cos(toolpath::kMaxTiltRad)) candidates.push_back(up);
        }
        bool eased = false;
        for (Vec3 axis : candidates) {
          if (!guarded(p.position_mm, axis) || strikes(axis)) continue;
          p.tool_axis = axis;
          ++plan.toolpaths[k].axes_eased;
          eased = true;
          break;
        }
        if (eased || !turning_back) continue;
        // The point cannot turn: the point before turns towards the layer's normal instead, where
        // the moves into it and out of it then clear.
        for (const double f : {0.25, 0.5, 0.75, 1.0}) {
          Vec3 axis = core::normalized(before->tool_axis * (1.0 - f) + n * f);
          if (!guarded(before->position_mm, axis)) continue;
          if (strikes_at(i - 1, before->position_mm, axis, before->deposit, before2, before2 ? before2->tool_axis : axis)) continue;
          if (strikes_at(i, p.position_mm, p.tool_axis, p.deposit, before, axis)) continue;
          before->tool_axis = axis;
          ++plan.toolpaths[k].axes_eased;
          break;
        }
      }
    }
    // Each travel leaves with the axis of the point before it and arrives with that of the point
    // after it, as eased.
    for (std::size_t j = 0; j < paths.size(); ++j) {
      if (paths[j].kind != toolpath::PathKind::kTravel || paths[j].points.empty()) continue;
      if (j > 0 && !paths[j - 1].points.empty()) paths[j].points.front().tool_axis = paths[j - 1].points.back().tool_axis;
      if (j + 1 < paths.size() && !paths[j + 1].points.empty()) paths[j].points.back().tool_axis = paths[j + 1].points.front().tool_axis;
    }
  });
  std::uint64_t eased = 0;
  for (const toolpath::LayerToolpaths& lt : plan.toolpaths) eased += lt.axes_eased;
  plan.tilts_eased += eased - eased_before;
}

namespace {

// The axis to leave P along to the sphere (CENTRE, RADIUS), or to come in along to P, for the
// transit: A itself when that leg keeps the head clear of the plate, the table and the deposit,
// else A turned up towards +Z by the least of kLegRaiseStepDeg, 2·kLegRaiseStepDeg, … up to
// toolpath::kMaxTiltRad whose leg, and whose turn in place at P from A, are clear; A when none is.
// (An axis below the horizon leaving a tip low on the part runs the head down into the table on
// the way out: a blade on an impeller's flaring hub, built along its normal 16° below the horizon.)
Vec3 leg_axis(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before, double clearance_mm,
              double margin_mm, Vec3 p, Vec3 a, Vec3 centre, double radius) {
  const Vec3 up{0, 0, 1};
  const double from_up = turn_rad(a, up), steps = std::floor(toolpath::kMaxTiltRad * 180.0 / kPi / kLegRaiseStepDeg + 1e-9);
  for (double k = 0.0; k <= steps; k += 1.0) {
    const double turn = k * kLegRaiseStepDeg * kPi / 180.0;
    if (k > 0.0 && turn > from_up) break;  // past vertical
    const Vec3 axis = k == 0.0 ? a : axis_between(a, up, turn / from_up);
    const Vec3 q = ray_exit(p, axis, centre, radius);
    if (clear_move(model, deposit, before, clearance_mm, margin_mm, p, axis, q, axis) &&
        (k == 0.0 || clear_move(model, deposit, before, clearance_mm, margin_mm, p, a, p, axis))) {
      return axis;
    }
  }
  return a;
}

}  // namespace

std::vector<TransitPoint> clear_travel(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before,
                                       double clearance_mm, double margin_mm, Vec3 from, Vec3 a, Vec3 to, Vec3 b, Vec3 centre,
                                       double radius) {
  a = core::normalized(a), b = core::normalized(b);
  if (clear_move(model, deposit, before, clearance_mm, margin_mm, from, a, to, b)) return {};
  for (const double lift : kLiftsMm) {
    const Vec3 p = from + a * lift, q = to + b * lift;
    if (core::norm(p - centre) > radius && core::norm(q - centre) > radius) break;  // the sphere is shorter from here
    if (clear_move(model, deposit, before, clearance_mm, margin_mm, from, a, p, a) &&
        clear_move(model, deposit, before, clearance_mm, margin_mm, p, a, q, b) &&
        clear_move(model, deposit, before, clearance_mm, margin_mm, q, b, to, b)) {
      return {{p, a}, {q, b}};
    }
  }
  // Out and in along axes that keep the head clear on the legs, turned in place at either end.
  const Vec3 out = leg_axis(model, deposit, before, clearance_mm, margin_mm, from, a, centre, radius);
  const Vec3 in = leg_axis(model, deposit, before, clearance_mm, margin_mm, to, b, centre, radius);
  std::vector<TransitPoint> path;
  if (core::norm(out - a) > 0.0) path.push_back({from, out});  // a itself when not turned
  const std::vector<TransitPoint> over = transit(from, out, to, in, centre, radius);
  path.insert(path.end(), over.begin(), over.end());
  if (core::norm(in - b) > 0.0) path.push_back({to, in});
  return path;
}

std::vector<TransitPoint> layer_travel(const machine::BuildModel& model, const verify::DepositCheck& deposit, std::size_t before,
                                       double clearance_mm, double margin_mm, Vec3 from, Vec3 a, Vec3 to, Vec3 b) {
  a = core::normalized(a), b = core::normalized(b);
  // FROM and TO are deposit points (their guard took them): the samples between them only.
  const auto clear_between = [&](Vec3 p, Vec3 pa, Vec3 q, Vec3 qb, bool from_end, bool to_end, double plate_mm) {
    return clear_samples(p, pa, q, qb, from_end ? 1 : 0, !to_end,
                         [&](Vec3 tip, Vec3 axis) { return clear_at(model, deposit, before, plate_mm, margin_mm, tip, axis); });
  };
  if (clear_between(from, a, to, b, true, true, 0.0)) return {};
  for (const double lift : kLiftsMm) {
    const Vec3 p = from + a * lift, q = to + b * lift;
    if (clear_between(from, a, p, a, true, false, clearance_mm) && clear_between(p, a, q, b, false, false, clearance_mm) &&
        clear_between(q, b, to, b, false, true, clearance_mm)) {
      return {{p, a}, {q, b}};
    }
  }
  return {};
}

}  // namespace polyaxis::planner::detail
