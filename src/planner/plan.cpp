#include "polyaxis/planner/plan.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <set>

#include <tbb/parallel_for.h>

#include "core/arena.h"
#include "polyaxis/core/progress.h"
#include "polyaxis/geom2d/clip.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/planner/plan_part.h"
#include "polyaxis/slicing/section.h"
#include "clearance.h"
#include "fidelity.h"
#include "reach.h"
#include "sequence.h"
#include "support.h"
#include "transit.h"
#include "unwind.h"

namespace polyaxis::planner {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The transit sphere's radius exceeds the part's by the retract distance and this share of it more,
// so the chords between transit points (transit.h) stay clear of the retract points' sphere.
constexpr double kTransitMarginShare = 0.5;

// The tilt of the torch may change at this share of the tilt axis's speed limit at the deposit feed.
constexpr double kRotaryShare = 0.5;
// A placed region reaching further than this share of the thinnest layer below the plate's top
// goes into the plate; less is inside the first layer's own rounding of the base.
constexpr double kBelowPlateLayerShare = 0.5;
// Halvings of a move whose axis turn brings the head too close to the plate (guard_axes).
constexpr int kMaxGuardDepth = 8;
// A layer whose bottom is within this of the plate's top is laid on the plate.
constexpr double kOnPlateMm = 1e-6;
// A layer whose normal's z reaches 1 − this is upright.
constexpr double kUprightCos = 1e-9;

double angle_deg(Vec3 a, Vec3 b) {
  const double c = core::dot(core::normalized(a), core::normalized(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / kPi;
}

// What stands on the plate: the box of the regions' material within HEIGHT_MM of the plate's top
// (each triangle's part below that height; the placed frame). The plate lies under it.
core::Box3 footprint_on_plate(const std::vector<PlanRegion>& regions, double height_mm) {
  core::Box3 box;
  for (const PlanRegion& r : regions) {
    const auto& v = r.mesh.vertices;
    for (const auto& t : r.mesh.triangles) {
      for (int e = 0; e < 3; ++e) {
        const Vec3 p = v[t[e]], q = v[t[(e + 1) % 3]];
        if (p.z <= height_mm) box.add(p);
        if ((p.z < height_mm) != (q.z < height_mm)) box.add(p + (q - p) * ((height_mm - p.z) / (q.z - p.z)));
      }
    }
  }
  return box;
}

// After placement: every region above the plate, every direction within reach; the build model.
core::Status place_checks(const std::vector<PlanRegion>& regions, const machine::MachineConfig& machine,
                          const process::ProcessConfig& process, Plan& plan) {
  for (const PlanRegion& r : regions) {
    double low = INFINITY;
    for (const Vec3& v : r.mesh.vertices) low = std::min(low, v.z);
    if (low < -kBelowPlateLayerShare * process.layer_min_mm) {
      return core::make_error(core::ErrorCode::kInfeasible,
                              fmt::format("region {} (build direction {:.3f}, {:.3f}, {:.3f}) reaches {:.2f} mm below the substrate's top "
                                          "when the first region stands on it: build from the part's lowest base (--root-base z-min) "
                                          "or with --strategy single",
                                          r.id, r.direction.x, r.direction.y, r.direction.z, -low));
    }
  }
  const core::Box3 box = footprint_on_plate(regions, process.layer_max_mm);
  plan.build_model = machine::make_build_model(machine, process, box.min.x, box.min.y, box.max.x, box.max.y);
  std::vector<PlanRegion> deposited;
  for (const PlanRegion& r : regions) {
    if (!r.prebuilt) {
      deposited.push_back(r);
      continue;
    }
    if (!machine::add_prebuilt(plan.build_model.prebuilt, r.mesh.vertices, r.mesh.triangles, machine::kPrebuiltSpacingBeads * process.bead_width_mm)) {
      return core::make_error(core::ErrorCode::kInfeasible,
                              fmt::format("prebuilt region {}: its surface needs more than {} samples {:.3f} mm apart (a bead of {} mm)", r.id,
                                          machine::kMaxPrebuiltSamples, machine::kPrebuiltSpacingBeads * process.bead_width_mm,
                                          process.bead_width_mm));
    }
  }
  if (auto s = detail::check_region_reach(deposited, machine, process); !s) return s;
  return detail::check_region_travel(deposited, machine);
}

// Adds to OUT the guarded points strictly between A and B needed for the head to stay clear of
// the plate and the table along the move (tip straight, axis along the great circle), checked at
// a quarter, a half and three quarters; at most kMaxGuardDepth halvings.
template <typename Guard>
core::Status refine_between(const machine::BuildModel& model, const toolpath::PathPoint& a, const toolpath::PathPoint& b, int depth,
                            std::vector<toolpath::PathPoint>& out, Guard& guard) {
  if (depth >= kMaxGuardDepth || core::norm(a.tool_axis - b.tool_axis) < 1e-9) return {};
  bool clear = true;
  for (const double u : {0.25, 0.5, 0.75}) {
    const Vec3 tip = a.position_mm + (b.position_mm - a.position_mm) * u;
    const Vec3 axis = core::normalized(a.tool_axis * (1.0 - u) + b.tool_axis * u);
    clear = clear && machine::head_clearance_mm(model, tip, axis, 0.0) >= 0.0;
  }
  if (clear) return {};
  toolpath::PathPoint mid = b;
  mid.position_mm = (a.position_mm + b.position_mm) * 0.5;
  mid.tool_axis = core::normalized(a.tool_axis + b.tool_axis);
  if (auto s = guard(mid); !s) return s;
  if (auto s = refine_between(model, a, mid, depth + 1, out, guard); !s) return s;
  out.push_back(mid);
  return refine_between(model, mid, b, depth + 1, out, guard);
}

// Keeps every tool axis of REGION's PATHS inside the machine's reach with the head clear of the
// plate and the table; the layers laid on the plate get the torch along the layer's normal.
core::Status guard_axes(Plan& plan, const machine::MachineConfig& machine, const PlanOptions& options, const PlanRegion& region,
                        const slicing::SliceResult& layers, std::vector<toolpath::LayerToolpaths>& paths) {
  const double reach = detail::reach_rad(machine);
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const slicing::Layer& layer = layers.layers[k];
    const bool on_plate = layer.frame.d.z > 1.0 - 1e-9 && std::abs(layer.height_mm - layer.below_mm) <= kOnPlateMm;
    auto guard = [&](toolpath::PathPoint& p) -> core::Status {
      Vec3 axis = on_plate ? layer.frame.d : p.tool_axis;
      if (!detail::guard_axis(machine, plan.build_model, reach, options.head_clearance_mm, options.retract_mm, p.position_mm, layer.frame.d,
                              axis)) {
        return core::make_error(
            core::ErrorCode::kMachineLimit,
            fmt::format("region {} layer {}: at ({:.2f}, {:.2f}, {:.2f}) on the table no tool axis within {:.0f} deg of the layer's "
                        "normal ({:.3f}, {:.3f}, {:.3f}) keeps the head {:.1f} mm clear of the plate and the table (nozzle "
                        "cylinder r {:.1f} mm at {:.1f} mm) inside the machine's limits: a slimmer head (nozzle.cylinder_radius_mm), "
                        "a region built further from the plate or --strategy single would make it buildable",
                        region.id, layer.index, p.position_mm.x, p.position_mm.y, p.position_mm.z, toolpath::kMaxTiltRad * 180.0 / kPi,
                        layer.frame.d.x, layer.frame.d.y, layer.frame.d.z, options.head_clearance_mm,
                        machine.nozzle.cylinder_radius_mm, machine.nozzle.cone_height_mm));
      }
      if (core::norm(p.tool_axis - axis) > 1e-12) ++plan.axes_turned, ++paths[k].axes_turned;
      p.tool_axis = axis;
      return {};
    };
    for (toolpath::Path& path : paths[k].paths) {
      for (toolpath::PathPoint& p : path.points) {
        if (auto s = guard(p); !s) return s;
      }
      // Both ends clear do not make the turn between them clear where a head circle crosses the
      // plate's edge: a point whose turn from its neighbour is not clear takes that one's axis
      // when it is clear there (forward, then backward for the path's first points).
      // True when the move between the two is clear at the end (P's axis taken or not); P's axis
      // changed sets TURNED.
      auto take_neighbours = [&](std::size_t i, std::size_t from, bool& turned) {
        toolpath::PathPoint& p = path.points[i];
        const toolpath::PathPoint& q = path.points[from];
        turned = false;
        if (detail::move_clear(plan.build_model, options.head_clearance_mm, q.position_mm, q.tool_axis, p.position_mm, p.tool_axis)) return true;
        Vec3 axis = q.tool_axis;
        if (detail::guard_axis(machine, plan.build_model, reach, options.head_clearance_mm, options.retract_mm, p.position_mm, layer.frame.d, axis) &&
            detail::move_clear(plan.build_model, options.head_clearance_mm, q.position_mm, q.tool_axis, p.position_mm, axis)) {
          p.tool_axis = axis;
          ++plan.axes_turned, ++paths[k].axes_turned;
          turned = true;
          return true;
        }
        return false;
      };
      // Forward, the move into point i is left clear or not with both its ends as they stay (the
      // pass turns only point i there); backward, a move found clear forward whose later end was
      // not turned since is not checked again.
      std::vector<char> clear_forward(path.points.size(), 0);
      bool turned = false;
      for (std::size_t i = 1; i < path.points.size(); ++i) clear_forward[i] = take_neighbours(i, i - 1, turned) ? 1 : 0;
      bool later_turned = false;
      for (std::size_t i = path.points.size(); i-- > 1;) {
        if (clear_forward[i] && !later_turned) continue;
        take_neighbours(i - 1, i, turned);
        later_turned = turned;
      }
      // Between two guarded points the axis turns along the way: where the head would come too
      // close in between, a guarded point is added at the middle (the path keeps its shape).
      std::vector<toolpath::PathPoint> refined;
      refined.reserve(path.points.size());
      for (std::size_t i = 0; i < path.points.size(); ++i) {
        if (i > 0) {
          if (auto s = refine_between(plan.build_model, path.points[i - 1], path.points[i], 0, refined, guard); !s) return s;
        }
        refined.push_back(path.points[i]);
      }
      path.points = std::move(refined);
    }
  }
  return {};
}

// The first bead of the plan must be laid on the plate: a first region whose lowest layers are all
// thinner than a bead would start in mid-air.
core::Status first_deposit_on_plate(const Plan& plan, const process::ProcessConfig& process) {
  for (const toolpath::LayerToolpaths& lt : plan.toolpaths) {
    double low = INFINITY;
    for (const toolpath::Path& path : lt.paths) {
      for (const toolpath::PathPoint& p : path.points) {
        if (p.deposit) low = std::min(low, p.position_mm.z);
      }
    }
    if (low == INFINITY) continue;
    if (low <= process.layer_max_mm) return {};
    const std::uint32_t region = plan.region_of_layer[lt.layer];
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("region {} would start {:.2f} mm above the substrate, in mid-air: its layers below are thinner "
                                        "than a bead ({:.2f} mm); {} would ground it",
                                        region, low, process.bead_width_mm,
                                        plan.placed_regions.size() > 1 ? "another root base (--root-base) or --strategy single"
                                                                       : "another build direction (--dir) standing the part on a face"));
  }
  return {};
}

bool has_prebuilt(const std::vector<PlanRegion>& regions) {
  return std::any_of(regions.begin(), regions.end(), [](const PlanRegion& r) { return r.prebuilt; });
}

// The surface of REGIONS' prebuilt ones (placed), the base of conformal layers: null when there are
// none, or when LAYERS asks for neither conformal nor automatic layers.
std::shared_ptr<const mesh::SurfaceDistance> prebuilt_surface(const std::vector<PlanRegion>& regions, LayerChoice layers) {
  if (!has_prebuilt(regions) || (layers != LayerChoice::kConformal && layers != LayerChoice::kAuto)) return nullptr;
  mesh::Mesh all;
  for (const PlanRegion& r : regions) {
    if (!r.prebuilt) continue;
    const auto offset = static_cast<std::uint32_t>(all.vertices.size());
    all.vertices.insert(all.vertices.end(), r.mesh.vertices.begin(), r.mesh.vertices.end());
    for (io::Triangle t : r.mesh.triangles) all.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  return std::make_shared<const mesh::SurfaceDistance>(all);
}

// TRUNK (part frame) placed, the base of conformal layers of the branches on it: null unless LAYERS
// asks for conformal or automatic layers.
std::shared_ptr<const mesh::SurfaceDistance> trunk_surface(const mesh::Mesh& trunk, const Placement& placement, LayerChoice layers) {
  if (layers != LayerChoice::kConformal && layers != LayerChoice::kAuto) return nullptr;
  mesh::Mesh placed = trunk;
  for (Vec3& v : placed.vertices) v = placement.apply(v);
  return std::make_shared<const mesh::SurfaceDistance>(placed);
}

// A prebuilt region's parent and the regions it rests on are prebuilt too: a region cannot be on
// the table before the one it grows from is built.
core::Status check_prebuilt(const std::vector<PlanRegion>& regions) {
  std::set<std::uint32_t> prebuilt;
  for (const PlanRegion& r : regions) {
    if (r.prebuilt) prebuilt.insert(r.id);
  }
  for (const PlanRegion& r : regions) {
    if (!r.prebuilt) continue;
    std::vector<std::uint32_t> below = r.rests_on;
    if (r.parent) below.push_back(*r.parent);
    for (const std::uint32_t b : below) {
      if (prebuilt.count(b)) continue;
      return core::make_error(core::ErrorCode::kUsage,
                              fmt::format("region {} cannot be prebuilt: it grows from region {}, which is not (the prebuilt regions are "
                                          "the root and regions grown from prebuilt ones)",
                                          r.id, b));
    }
  }
  return {};
}

// Puts the layers (with their toolpaths) in build order (sequence.h) and numbers them in that order.
void order_layers(Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process) {
  plan.c_space_radius_mm = detail::nozzle_radius_mm(machine.nozzle) + process.rules.c_space_margin_mm;
  const detail::Sequence seq = detail::sequence_layers(plan.layers.layers, plan.region_of_layer, plan.placed_regions, plan.c_space_radius_mm,
                                                        process.rules.interleave);
  const std::size_t n = seq.order.size();
  std::vector<std::uint32_t> position(n);
  for (std::size_t k = 0; k < n; ++k) position[seq.order[k]] = static_cast<std::uint32_t>(k);
  std::vector<slicing::Layer> layers(n);
  std::vector<toolpath::LayerToolpaths> paths(n);
  std::vector<std::uint32_t> regions(n);
  plan.order.assign(n, {});
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = seq.order[k];
    const auto index = static_cast<std::uint32_t>(k);
    layers[k] = std::move(plan.layers.layers[i]);
    layers[k].index = index;
    paths[k] = std::move(plan.toolpaths[i]);
    paths[k].layer = index;
    for (toolpath::Path& path : paths[k].paths) path.layer = index;
    for (toolpath::ThinRegion& thin : paths[k].thin) thin.layer = index;
    regions[k] = plan.region_of_layer[i];
    plan.order[k] = seq.records[i];
    for (std::uint32_t& j : plan.order[k].interferes_with) j = position[j];
  }
  plan.layers.layers = std::move(layers);
  plan.toolpaths = std::move(paths);
  plan.region_of_layer = std::move(regions);
}

// The program: each layer approached along its first tool axis, its paths in order, a retract
// along the last; between layers and regions the travel of clearance.h (straight where clear).
void make_program(Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanOptions& options,
                  const verify::DepositCheck& deposit) {
  const double deposit_feed = process.deposit_feed_mm_s, travel_feed = process.travel_feed_mm_s;
  std::uint32_t region_id = 0;
  // The sphere the tool crosses where nothing shorter is clear: around the placed part, with room for the retract.
  core::Box3 placed_box;
  for (const PlanRegion& r : plan.placed_regions) {
    for (const Vec3& v : r.mesh.vertices) placed_box.add(v);
  }
  const Vec3 sphere_centre = (placed_box.min + placed_box.max) * 0.5;
  double sphere_radius = 0.0;
  for (const PlanRegion& r : plan.placed_regions) {
    for (const Vec3& v : r.mesh.vertices) sphere_radius = std::max(sphere_radius, core::norm(v - sphere_centre));
  }
  sphere_radius += options.retract_mm * (1.0 + kTransitMarginShare);
  const double reach = detail::reach_rad(machine), margin = detail::kDepositMarginBeads * process.bead_width_mm;
  const double tilted_cos = std::cos(kTiltedDeg * kPi / 180.0);
  const std::uint32_t root = plan.placed_regions.empty() ? 0 : plan.placed_regions.front().id;
  const double head_reach = detail::nozzle_radius_mm(plan.build_model.nozzle);
  auto push = [&](Vec3 tip, Vec3 axis, bool on, std::uint32_t layer, std::string comment) {
    post::ProgramPoint p;
    p.tip_part_mm = tip;
    p.tool_axis_part = axis;
    p.feed_mm_s = on ? deposit_feed : travel_feed;
    p.process_on = on;
    p.layer = layer;
    p.region = region_id;
    p.comment_if_new_block = std::move(comment);
    plan.program.push_back(std::move(p));
  };
  std::size_t flat = 0;  // the path points so far (planned_points' index)
  for (const toolpath::LayerToolpaths& lt : plan.toolpaths) {
    region_id = plan.region_of_layer[lt.layer];
    plan.deposit_length_mm += lt.deposit_length_mm;
    plan.travel_length_mm += lt.travel_length_mm;
    plan.thin_regions += lt.thin.size();
    for (const auto& thin : lt.thin) plan.thin_area_mm2 += thin.area_mm2;
    bool first_in_layer = true;
    const Vec3 normal = plan.layers.layers[lt.layer].frame.d;
    auto turned = [&](const toolpath::PathPoint& p) { return core::dot(core::normalized(p.tool_axis), normal) < tilted_cos; };
    const bool exposed = region_id != root && detail::others_above(plan, lt.layer, head_reach);
    for (const toolpath::Path& path : lt.paths) {
      if (path.points.empty()) continue;
      const char* kind = path.kind == toolpath::PathKind::kPerimeter ? "perimeter" : (path.kind == toolpath::PathKind::kFill ? "fill" : "travel");
      // The G-code writer prefixes "layer N region R" to a new block's comment.
      const std::string comment = path.kind == toolpath::PathKind::kPerimeter ? fmt::format("perimeter {}", path.perimeter_index)
                                  : path.gap_fill                               ? std::string("gap fill")
                                                                                : std::string(kind);
      if (first_in_layer) {
        const toolpath::PathPoint& p0 = path.points.front();
        const Vec3 approach = p0.position_mm + core::normalized(p0.tool_axis) * options.retract_mm;
        if (!plan.program.empty()) {
          const post::ProgramPoint last = plan.program.back();
          const auto via = detail::clear_travel(plan.build_model, deposit, flat, options.head_clearance_mm, margin, last.tip_part_mm,
                                                last.tool_axis_part, approach, p0.tool_axis, sphere_centre, sphere_radius);
          plan.travel_detours += via.empty() ? 0 : 1;
          bool first = true;
          for (TransitPoint t : via) {
            // Below the part's middle the sphere's outward axis points the head at the plate:
            // turned up until it clears, and lifted above the plate where no turn does.
            if (!detail::guard_axis(machine, plan.build_model, reach, options.head_clearance_mm, 0.0, t.tip, t.axis, t.axis)) {
              t.axis = {0, 0, 1};
              t.tip.z = std::max(t.tip.z, options.head_clearance_mm);
            }
            push(t.tip, t.axis, false, lt.layer, first ? "transit" : "");
            first = false;
          }
        }
        push(approach, p0.tool_axis, false, lt.layer, "approach");
        first_in_layer = false;
      }
      if (path.kind == toolpath::PathKind::kTravel && path.points.size() == 2 && (turned(path.points[0]) || turned(path.points[1]) || exposed)) {
        // Between two paths of the layer the head may sweep through what the layer laid (the
        // torch turning back from a tilt) or what another region laid above it: around where so.
        const toolpath::PathPoint &from = path.points[0], &to = path.points[1];
        push(from.position_mm, from.tool_axis, false, lt.layer, comment);
        const auto via = detail::layer_travel(plan.build_model, deposit, flat, options.head_clearance_mm, margin, from.position_mm, from.tool_axis,
                                              to.position_mm, to.tool_axis);
        plan.travel_detours += via.empty() ? 0 : 1;
        for (const TransitPoint& t : via) push(t.tip, t.axis, false, lt.layer, "");
        push(to.position_mm, to.tool_axis, false, lt.layer, "");
        flat += path.points.size();
        continue;
      }
      for (std::size_t i = 0; i < path.points.size(); ++i) {
        const toolpath::PathPoint& p = path.points[i];
        push(p.position_mm, p.tool_axis, p.deposit, lt.layer, i == 0 ? comment : std::string());
      }
      flat += path.points.size();
    }
    if (!plan.program.empty() && !first_in_layer) {
      const post::ProgramPoint last = plan.program.back();
      push(last.tip_part_mm + core::normalized(last.tool_axis_part) * options.retract_mm, last.tool_axis_part, false, lt.layer,
           "retract");
    }
  }
}

// Counts the program's reorientations, each with its rule: a turn before a layer's first bead
// reorients for the layer (for its region when the layer before was another region's); after it,
// the tilt changes along the layer. Also the largest tilt while depositing.
void count_reorientations(Plan& plan) {
  std::uint32_t layer_region = plan.program.front().region, before_region = layer_region;
  bool deposited = false;
  for (std::size_t i = 0; i < plan.program.size(); ++i) {
    const post::ProgramPoint& p = plan.program[i];
    if (i > 0 && p.layer != plan.program[i - 1].layer) before_region = layer_region, layer_region = p.region, deposited = false;
    if (p.process_on) plan.max_tilt_deg = std::max(plan.max_tilt_deg, angle_deg(p.tool_axis_part, plan.layers.layers[p.layer].frame.d));
    const double turn = i > 0 ? angle_deg(p.tool_axis_part, plan.program[i - 1].tool_axis_part) : 0.0;
    if (turn > kReorientationDeg) {
      ++plan.reorientations;
      const char* rule = deposited ? kReorientTilt : (before_region != layer_region ? kReorientRegion : kReorientLayer);
      plan.reorientation_list.push_back({i, p.layer, turn, rule});
    }
    deposited = deposited || p.process_on;
  }
}

// The program from the toolpaths as they stand (make_program), with C's unwind points and the
// reorientations counted; the figures they give start from zero.
void finish_program(Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanOptions& options,
                    const verify::DepositCheck& deposit) {
  plan.program.clear();
  plan.deposit_length_mm = plan.travel_length_mm = plan.thin_area_mm2 = plan.max_tilt_deg = 0.0;
  plan.thin_regions = plan.travel_detours = plan.reorientations = 0;
  plan.reorientation_list.clear();
  make_program(plan, machine, process, options, deposit);
  if (plan.program.empty()) return;
  detail::keep_travel_within_reach(plan.program, detail::reach_rad(machine));
  plan.program = detail::insert_c_unwinds(plan.program, plan.layers.layers, machine);
  count_reorientations(plan);
}

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// What REGION's slicings share: its direction, the process's step, thickness range and overhang
// limit (with the step a tilted torch may take, where the torch can tilt).
slicing::SliceOptions region_slice_options(const PlanRegion& region, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                           const PlanOptions& options) {
  slicing::SliceOptions slice;
  slice.direction = region.direction;
  slice.layer_mm = process.layer_mm;
  slice.threads = options.threads;
  slice.min_mm = process.layer_min_mm;
  slice.max_mm = process.layer_max_mm;
  slice.limits.overhang_deg = process.self_supporting_deg;
  if (options.tilt_on_overhang && machine::has_rotary_axes(machine.kind)) {
    slice.limits.overhang_step_mm = process.max_step_bead_share * process.bead_width_mm;
  }
  return slice;
}

// The options of REGION's planar slicing: adaptive under the cusp and the overhang limit where the
// process's range is not one value, else uniform at its step.
slicing::SliceOptions planar_options(const PlanRegion& region, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                     const PlanOptions& options) {
  slicing::SliceOptions slice = region_slice_options(region, machine, process, options);
  slice.adaptive = process.adaptive_layers && process.layer_min_mm < process.layer_max_mm;
  if (slice.adaptive) {
    slice.limits.cusp_mm = process.cusp_mm;
  } else {
    slice.limits = {};
  }
  return slice;
}

// The options of REGION's tilted slicing: the process's thickness range, VolDiff and overhang.
slicing::SliceOptions tilted_options(const PlanRegion& region, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                     const PlanOptions& options) {
  slicing::SliceOptions slice = region_slice_options(region, machine, process, options);
  slice.tilted = true;
  slice.limits.voldiff = process.voldiff;
  return slice;
}

// The options of REGION's conformal slicing: levels of the distance from BASE (the prebuilt part's
// surface) at the process's step within its range, on the region refined where the distance bends,
// down to edges of kConformalEdgeBeads.
slicing::SliceOptions conformal_options(const PlanRegion& region, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                        const PlanOptions& options, std::shared_ptr<const mesh::SurfaceDistance> base) {
  slicing::SliceOptions slice = region_slice_options(region, machine, process, options);
  slice.limits = {};
  slice.conformal_base = std::move(base);
  slice.conformal_edge_mm = kConformalEdgeBeads * process.bead_width_mm;
  return slice;
}

// Checks that --layers LAYERS can be made on MACHINE with OPTIONS (kUsage otherwise).
core::Status check_layer_choice(const machine::MachineConfig& machine, const PlanOptions& options, bool has_base) {
  if (options.layers != LayerChoice::kTilted && options.layers != LayerChoice::kConformal) return {};
  const char* name = layer_choice_name(options.layers);
  if (!machine::has_rotary_axes(machine.kind)) {
    return core::make_error(core::ErrorCode::kUsage,
                            fmt::format("--layers {}: machine '{}' has no rotary axes to turn the torch with the layers", name, machine.name));
  }
  if (!options.tilt_on_overhang) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("--layers {} turns the torch with each layer; it contradicts --no-tilt", name));
  }
  if (options.layers == LayerChoice::kConformal && !has_base) {
    return core::make_error(core::ErrorCode::kUsage,
                            "--layers conformal: the layers follow a prebuilt part's surface; give one with --substrate or --prebuilt");
  }
  return {};
}

// REGION's layers by OPTIONS.layers. kAuto: the planar ones unless they leave overhang
// (slicing::overhang_estimate_mm2 with the step a tilted torch may take) and conformal layers on
// BASE (when there is a prebuilt part) or tilted ones leave less than kTiltedGainShare of it, the
// one that leaves less. A conformal slicing the region cannot take (it does not rest on the base,
// or a level folds over along its direction) leaves it planar, and says why. Sets the region's
// layers, layers_rule and layers_why.
core::Result<slicing::SliceResult> region_layers(PlanRegion& region, const mesh::EdgeTopology* topology, const machine::MachineConfig& machine,
                                                 const process::ProcessConfig& process, const PlanOptions& options,
                                                 const std::shared_ptr<const mesh::SurfaceDistance>& base) {
  if (auto s = check_layer_choice(machine, options, base != nullptr); !s) return s.error();
  const bool rotary = machine::has_rotary_axes(machine.kind);
  if (options.layers != LayerChoice::kAuto) {
    region.layers = options.layers == LayerChoice::kTilted      ? slicing::LayerStrategy::kTilted
                    : options.layers == LayerChoice::kConformal ? slicing::LayerStrategy::kConformal
                                                                : slicing::LayerStrategy::kPlanar;
    region.layers_rule = kLayersAsked;
    region.layers_why = fmt::format("--layers {}", layer_choice_name(options.layers));
    if (region.layers == slicing::LayerStrategy::kConformal) {
      auto conformal = slicing::slice(region.mesh, conformal_options(region, machine, process, options, base), topology);
      if (conformal || conformal.error().code != core::ErrorCode::kInfeasible) return conformal;
      region.layers = slicing::LayerStrategy::kPlanar;
      region.layers_why = fmt::format("--layers conformal refused, planar layers: {}", conformal.error().message);
      return slicing::slice(region.mesh, planar_options(region, machine, process, options), topology);
    }
    const auto o = region.layers == slicing::LayerStrategy::kTilted ? tilted_options(region, machine, process, options)
                                                                     : planar_options(region, machine, process, options);
    return slicing::slice(region.mesh, o, topology);
  }
  auto planar = slicing::slice(region.mesh, planar_options(region, machine, process, options), topology);
  if (!planar) return planar;
  const double step = options.tilt_on_overhang && rotary ? process.max_step_bead_share * process.bead_width_mm : 0.0;
  const double planar_mm2 = slicing::overhang_estimate_mm2(planar.value(), process.self_supporting_deg, step);
  region.layers = slicing::LayerStrategy::kPlanar;
  region.layers_rule = kLayersPlanar;
  if (planar_mm2 < kUnsupportedNoiseMm2 || !rotary || !options.tilt_on_overhang) {
    region.layers_why = planar_mm2 < kUnsupportedNoiseMm2 ? "planar layers leave no overhang"
                        : !rotary                          ? "planar layers: the machine has no rotary axes"
                                                           : "planar layers: the torch stays along the build direction (--no-tilt)";
    return planar;
  }
  slicing::SliceResult best = std::move(planar.value());
  double best_mm2 = planar_mm2;
  std::vector<std::string> figures{fmt::format("overhang {} mm2 on planar layers", area_text(planar_mm2))};
  auto consider = [&](slicing::LayerStrategy strategy, const slicing::SliceOptions& o, const char* rule) -> core::Status {
    const char* name = slicing::layer_strategy_name(strategy);
    auto layers = slicing::slice(region.mesh, o, topology);
    if (!layers && layers.error().code == core::ErrorCode::kInfeasible) {
      figures.push_back(fmt::format("{} layers refused: {}", name, layers.error().message));
      return {};
    }
    if (!layers) return layers.error();
    const double mm2 = slicing::overhang_estimate_mm2(layers.value(), process.self_supporting_deg, step);
    figures.push_back(fmt::format("{} mm2 on {} layers", area_text(mm2), name));
    if (mm2 < kTiltedGainShare * planar_mm2 && mm2 < best_mm2) {
      best = std::move(layers.value()), best_mm2 = mm2;
      region.layers = strategy, region.layers_rule = rule;
    }
    return {};
  };
  if (base) {
    if (auto s = consider(slicing::LayerStrategy::kConformal, conformal_options(region, machine, process, options, base), kLayersConformal); !s) {
      return s.error();
    }
  }
  slicing::SliceOptions tilted_slice = tilted_options(region, machine, process, options);
  tilted_slice.give_up_overhang_mm2 = std::min(best_mm2, kTiltedGainShare * planar_mm2);  // beyond it the tilted layers cannot be kept
  if (auto s = consider(slicing::LayerStrategy::kTilted, tilted_slice, kLayersTilted); !s) return s.error();
  region.layers_why = fmt::format("{}", fmt::join(figures, ", "));
  if (region.layers == slicing::LayerStrategy::kPlanar) region.layers_why += ": no other layers do better";
  return best;
}

// Where a prebuilt part rises within the process's least thickness under a layer's top, the layer
// is trimmed: a bead there would be thinner than the process allows (and the tip would touch the
// part); the next layer fills the pocket. Layers along the region's own direction (planar ones,
// and a tilted slicing's first) are trimmed against the prebuilt regions of REGIONS.
void trim_over_prebuilt(slicing::SliceResult& layers, const std::vector<PlanRegion>& regions, const PlanRegion& region, double min_mm) {
  const Vec3 d = core::normalized(region.direction);
  std::vector<std::unique_ptr<slicing::SectionContext>> contexts;
  for (const PlanRegion& r : regions) {
    if (r.prebuilt) contexts.push_back(std::make_unique<slicing::SectionContext>(r.mesh, d));
  }
  if (contexts.empty()) return;
  std::vector<std::uint32_t> candidates;
  slicing::SectionScratch scratch;
  for (slicing::Layer& layer : layers.layers) {
    // Conformal layers keep their distance from the prebuilt part by construction.
    if (layer.conformal || core::dot(layer.frame.d, d) < 1.0 - 1e-12 || layer.polygons.empty()) continue;
    const double h = layer.height_mm + layer.above_mm - min_mm;
    std::vector<geom2d::Ring> under;
    for (const auto& ctx : contexts) {
      if (h < ctx->min_height() || h > ctx->max_height()) continue;
      candidates.clear();
      for (std::uint32_t f = 0; f < ctx->mesh().triangles.size(); ++f) {
        if (ctx->face_min(f) <= h && ctx->face_max(f) >= h) candidates.push_back(f);
      }
      for (geom2d::Ring& ring : geom2d::rings_of(slicing::section(*ctx, h, layer.frame, candidates, scratch).polygons)) under.push_back(std::move(ring));
    }
    if (under.empty()) continue;
    layer.polygons = geom2d::difference_rings(geom2d::rings_of(layer.polygons), under);
    layer.area_mm2 = geom2d::area_mm2(layer.polygons);
  }
}

// The tilt may change no faster than the tilt axis turns at kRotaryShare of its limit while the tip
// moves at the deposit feed (degrees per mm of path).
double steady_turn_deg_per_mm(const machine::MachineConfig& machine, const process::ProcessConfig& process) {
  return kRotaryShare * machine.feed.rotary_max_deg_min / 60.0 / process.deposit_feed_mm_s;
}

// Slices REGION (placed) along its direction; REGIONS (placed): all of the plan's, for its prebuilt
// ones (trim_over_prebuilt). TOPOLOGY: the whole part's, for an undivided part (null otherwise).
// Reads nothing of the plan: regions are sliced side by side.
core::Result<slicing::SliceResult> slice_region(PlanRegion& region, const std::vector<PlanRegion>& regions, const mesh::EdgeTopology* topology,
                                                const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                                const PlanOptions& options, const std::shared_ptr<const mesh::SurfaceDistance>& base) {
  // A trunk's surface is the base of the branches on it only.
  static const std::shared_ptr<const mesh::SurfaceDistance> none;
  auto layers = region_layers(region, topology, machine, process, options, options.trunk && !region.on_trunk ? none : base);
  if (!layers) return layers;
  trim_over_prebuilt(layers.value(), regions, region, process.layer_min_mm);
  return layers;
}

// The toolpaths of REGION's LAYERS (the torch not yet guarded). Reads nothing of the plan: regions'
// toolpaths are made side by side (a region's gap fill is planned again bottom up, one layer
// after another, so side by side is where the second core goes).
core::Result<std::vector<toolpath::LayerToolpaths>> region_toolpaths(const PlanRegion& region, const slicing::SliceResult& layers,
                                                                     const machine::MachineConfig& machine,
                                                                     const process::ProcessConfig& process, const PlanOptions& options) {
  toolpath::ToolpathOptions tp;
  tp.bead_width_mm = process.bead_width_mm;
  tp.perimeters = options.perimeters;
  tp.self_supporting_deg = process.self_supporting_deg;
  tp.max_step_mm = process.max_step_bead_share * process.bead_width_mm;
  tp.tilt_on_overhang = options.tilt_on_overhang && machine::has_rotary_axes(machine.kind);
  tp.threads = options.threads;
  tp.region = region.id;
  tp.max_axis_turn_deg_per_mm = steady_turn_deg_per_mm(machine, process);
  // Gap fill in the first layer only where it stands upright on the plate's top (Z = 0 placed), or
  // lies on a prebuilt part's surface (conformal layers: their first level is on it everywhere).
  if (!layers.layers.empty()) {
    const slicing::Layer& first = layers.layers.front();
    tp.gap_fill_first_layer = layers.conformal_base != nullptr ||
                              (first.frame.d.z > 1.0 - kUprightCos && std::abs(first.height_mm - first.below_mm) <= kOnPlateMm);
  }
  return toolpath::make_toolpaths(region.mesh, layers, tp);
}

// Guards the torch of REGION's PATHS and appends its LAYERS and PATHS to PLAN, numbered after
// those there (regions in build order).
core::Status append_region(Plan& plan, const PlanRegion& region, slicing::SliceResult&& layers, std::vector<toolpath::LayerToolpaths>&& paths,
                           const machine::MachineConfig& machine, const PlanOptions& options) {
  if (auto s = guard_axes(plan, machine, options, region, layers, paths); !s) return s.error();
  // Layers are numbered across regions, in build order.
  const auto offset = static_cast<std::uint32_t>(plan.layers.layers.size());
  for (slicing::Layer& l : layers.layers) {
    l.index += offset;
    plan.layers.layers.push_back(std::move(l));
    plan.region_of_layer.push_back(region.id);
  }
  if (layers.conformal_base) plan.layers.conformal_base = layers.conformal_base;
  plan.layers.open_chains += layers.open_chains;
  plan.layers.total_area_mm2 += layers.total_area_mm2;
  plan.layers.volume_estimate_mm3 += layers.volume_estimate_mm3;
  for (toolpath::LayerToolpaths& lt : paths) {
    lt.layer += offset;
    for (toolpath::Path& path : lt.paths) path.layer += offset;
    plan.toolpaths.push_back(std::move(lt));
  }
  return {};
}

// Slices every region of REGIONS (placed) that is not prebuilt and makes its toolpaths, regions side
// by side, then appends them to PLAN in their order (append_region). The first region's error in
// that order is returned, as one region after another would. TOPOLOGY as slice_region's.
core::Status add_regions(Plan& plan, std::vector<PlanRegion>& regions, const mesh::EdgeTopology* topology, const machine::MachineConfig& machine,
                         const process::ProcessConfig& process, const PlanOptions& options,
                         const std::shared_ptr<const mesh::SurfaceDistance>& base) {
  auto stopped = [&] { return options.stop != nullptr && options.stop->load(std::memory_order_relaxed); };
  const core::Error stop_error{core::ErrorCode::kInfeasible, "stopped"};
  const std::size_t n = regions.size();
  const auto progress = core::ProgressScope::current();  // each region may run on a worker thread
  auto each_region = [&](auto&& work) {
    core::with_threads(options.threads, [&] {
      tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        const core::ProgressScope scope(progress);
        if (!regions[i].prebuilt && !stopped()) work(i);
      });
    });
  };
  auto t0 = Clock::now();
  std::vector<std::optional<core::Result<slicing::SliceResult>>> layers(n);
  each_region([&](std::size_t i) { layers[i].emplace(slice_region(regions[i], regions, topology, machine, process, options, base)); });
  plan.times.slice_s += since(t0);
  t0 = Clock::now();
  std::vector<std::optional<core::Result<std::vector<toolpath::LayerToolpaths>>>> paths(n);
  each_region([&](std::size_t i) {
    if (layers[i]->ok()) paths[i].emplace(region_toolpaths(regions[i], layers[i]->value(), machine, process, options));
  });
  for (std::size_t i = 0; i < n; ++i) {
    if (regions[i].prebuilt) continue;
    if (stopped() || !layers[i]) return stop_error;
    if (!layers[i]->ok()) return layers[i]->error();
    if (!paths[i]) return stop_error;
    if (!paths[i]->ok()) return paths[i]->error();
    if (auto s = append_region(plan, regions[i], std::move(layers[i]->value()), std::move(paths[i]->value()), machine, options); !s) return s;
  }
  plan.times.toolpath_s += since(t0);
  return {};
}

}  // namespace

const char* layer_choice_name(LayerChoice c) {
  switch (c) {
    case LayerChoice::kPlanar: return "planar";
    case LayerChoice::kTilted: return "tilted";
    case LayerChoice::kConformal: return "conformal";
    case LayerChoice::kAuto: return "auto";
  }
  return "?";
}

Placement rotation_to_z(Vec3 d) {
  Placement p;
  d = core::normalized(d);
  const Vec3 z{0, 0, 1};
  const Vec3 k = core::cross(d, z);  // the axis, |k| = sin of the angle
  const double s = core::norm(k), c = core::dot(d, z);
  if (s < 1e-12) {
    if (c < 0.0) p.rows[1] = {0, -1, 0}, p.rows[2] = {0, 0, -1};  // a half turn about X
    return p;
  }
  // Rodrigues: R = I + [k]× + [k]×² (1 − c) / s², with k = d × z.
  const double f = (1.0 - c) / (s * s);
  p.rows[0] = {1.0 - f * (k.y * k.y + k.z * k.z), -k.z + f * k.x * k.y, k.y + f * k.x * k.z};
  p.rows[1] = {k.z + f * k.x * k.y, 1.0 - f * (k.x * k.x + k.z * k.z), -k.x + f * k.y * k.z};
  p.rows[2] = {-k.y + f * k.x * k.z, k.x + f * k.y * k.z, 1.0 - f * (k.x * k.x + k.y * k.y)};
  return p;
}

void measure_plan_fidelity(Plan& plan, const process::ProcessConfig& process) {
  const auto t0 = Clock::now();
  double deposited_volume = 0.0;
  for (const PlanRegion& r : plan.placed_regions) deposited_volume += r.prebuilt ? 0.0 : std::abs(mesh::signed_volume(r.mesh));
  detail::measure_fidelity(plan, deposited_volume, kConformalEdgeBeads * process.bead_width_mm);
  plan.fidelity.measured = true;
  plan.times.fidelity_s += since(t0);
}

core::Result<Plan> make_plan(const mesh::RepairedMesh& part, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                             const PlanOptions& options, const std::vector<PlanRegion>& given_regions) {
  Plan plan;
  if (!core::is_finite(options.direction) || core::norm(options.direction) < 1e-12) {
    return core::make_error(core::ErrorCode::kUsage, "--dir: the build direction must be a finite non-zero vector");
  }
  const Vec3 d = core::normalized(given_regions.empty() ? options.direction : given_regions.front().direction);
  // Placement: the build direction turned to the table's +Z, the first region's base on the
  // plate's top (Z = 0), the footprint centred on the machine's work centre (the rotary axis, or
  // the middle of a 3-axis machine's travel).
  plan.placement = rotation_to_z(d);
  double lowest = INFINITY;
  core::Box3 box;
  for (const Vec3& v : part.mesh.vertices) box.add(plan.placement.rotate(v));
  for (const PlanRegion& r : given_regions) {  // a substrate may reach beyond the part
    for (const Vec3& v : r.mesh.vertices) box.add(plan.placement.rotate(v));
  }
  for (const Vec3& v : given_regions.empty() ? part.mesh.vertices : given_regions.front().mesh.vertices) {
    lowest = std::min(lowest, plan.placement.rotate(v).z);
  }
  const Vec3 centre = machine::work_centre_mm(machine);
  plan.placement.translation_mm = {centre.x - (box.min.x + box.max.x) * 0.5, centre.y - (box.min.y + box.max.y) * 0.5, -lowest};
  if (auto s = check_prebuilt(given_regions); !s) return s.error();
  std::vector<PlanRegion> regions = given_regions;
  // The prebuilt regions first (the root among them): they are on the table before anything is laid.
  std::stable_partition(regions.begin(), regions.end(), [](const PlanRegion& r) { return r.prebuilt; });
  if (regions.empty()) {
    PlanRegion whole;
    whole.mesh = part.mesh;
    whole.direction = d;
    // The middle of the footprint, on the table, in the part's frame.
    const Vec3 on_table{(box.min.x + box.max.x) * 0.5, (box.min.y + box.max.y) * 0.5, lowest};
    whole.base_point = plan.placement.unrotate(on_table);
    whole.volume_mm3 = std::abs(mesh::signed_volume(part.mesh));
    regions.push_back(std::move(whole));
  }
  for (PlanRegion& r : regions) {
    for (Vec3& v : r.mesh.vertices) v = plan.placement.apply(v);
    r.base_point = plan.placement.apply(r.base_point);
    r.direction = plan.placement.rotate(core::normalized(r.direction));
    r.base_normal = plan.placement.rotate(core::normalized(r.base_normal));
  }
  if (auto s = place_checks(regions, machine, process, plan); !s) return s.error();
  plan.regions = static_cast<std::uint32_t>(regions.size());
  const std::shared_ptr<const mesh::SurfaceDistance> base = options.trunk ? trunk_surface(*options.trunk, plan.placement, options.layers)
                                                                          : prebuilt_surface(regions, options.layers);
  auto stopped = [&] { return options.stop != nullptr && options.stop->load(std::memory_order_relaxed); };
  const core::Error stop_error{core::ErrorCode::kInfeasible, "stopped"};
  // The whole part's topology is valid only for the unsplit part.
  if (auto st = add_regions(plan, regions, given_regions.empty() ? &part.topology : nullptr, machine, process, options, base); !st) {
    return st.error();
  }
  plan.placed_regions = regions;
  if (plan.layers.layers.empty()) {
    return core::make_error(core::ErrorCode::kInfeasible, has_prebuilt(regions) ? "nothing to build: the prebuilt part is the whole part"
                                                                                : "nothing to build: the part has no layers");
  }
  if (stopped()) return stop_error;
  auto t0 = Clock::now();
  order_layers(plan, machine, process);
  // Tilts eased where the head would strike what is built before them, in build order; the support
  // check then judges the torch as it will be.
  const verify::DepositCheck deposit(plan.build_model, detail::planned_points(plan), process.bead_width_mm);
  detail::ease_tilts(plan, machine, options, deposit, process.bead_width_mm, process.deposit_feed_mm_s);
  plan.times.sequence_s = since(t0);
  t0 = Clock::now();
  detail::check_support(plan, process);
  plan.times.support_s = since(t0);
  if (options.measure_fidelity) measure_plan_fidelity(plan, process);
  // On a prebuilt part the first bead rests on its surface (the read-back check judges that).
  if (!has_prebuilt(regions)) {
    if (auto s = first_deposit_on_plate(plan, process); !s) return s.error();
  }
  if (stopped()) return stop_error;
  t0 = Clock::now();
  finish_program(plan, machine, process, options, deposit);
  if (plan.program.empty()) return core::make_error(core::ErrorCode::kInfeasible, "nothing to build: every layer is thinner than a bead");
  plan.times.program_s = since(t0);
  return plan;
}

std::size_t relieve_collisions(Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                               const PlanOptions& options, const std::vector<std::pair<std::uint32_t, Vec3>>& places) {
  // The points to turn: per place, the ends of the layer's move nearest the tip.
  std::set<std::pair<std::uint32_t, std::uint32_t>> marked;
  for (const auto& [layer, tip] : places) {
    if (layer >= plan.toolpaths.size()) continue;
    std::uint32_t flat = 0, best = 0;
    double best_d = INFINITY;
    const toolpath::PathPoint* previous = nullptr;
    for (const toolpath::Path& path : plan.toolpaths[layer].paths) {
      for (const toolpath::PathPoint& p : path.points) {
        const Vec3 a = previous ? previous->position_mm : p.position_mm, ab = p.position_mm - a;
        const double l2 = core::dot(ab, ab), u = l2 > 0.0 ? std::clamp(core::dot(tip - a, ab) / l2, 0.0, 1.0) : 0.0;
        const double d = core::norm(a + ab * u - tip);
        if (d < best_d) best_d = d, best = flat;
        previous = &p, ++flat;
      }
    }
    if (best_d > process.bead_width_mm) continue;  // a travel away from the path: not the torch's tilt
    marked.insert({layer, best});
    if (best > 0) marked.insert({layer, best - 1});
  }
  const double reach = detail::reach_rad(machine);
  std::size_t turned = 0;
  for (const auto& [layer, index] : marked) {
    toolpath::PathPoint* p = nullptr;
    std::vector<const toolpath::PathPoint*> neighbours;  // the points the head moves from and to along the path
    std::uint32_t flat = 0;
    for (toolpath::Path& path : plan.toolpaths[layer].paths) {
      if (index < flat + path.points.size()) {
        const std::size_t i = index - flat;
        p = &path.points[i];
        if (i > 0) neighbours.push_back(&path.points[i - 1]);
        if (i + 1 < path.points.size()) neighbours.push_back(&path.points[i + 1]);
        break;
      }
      flat += static_cast<std::uint32_t>(path.points.size());
    }
    if (p == nullptr) continue;
    auto turns_clear = [&](Vec3 axis) {
      return std::all_of(neighbours.begin(), neighbours.end(), [&](const toolpath::PathPoint* q) {
        return detail::move_clear(plan.build_model, options.head_clearance_mm, q->position_mm, q->tool_axis, p->position_mm, axis);
      });
    };
    const Vec3 n = plan.layers.layers[layer].frame.d, up{0, 0, 1};
    const Vec3 candidates[] = {n, core::normalized(n + up), up};
    for (std::uint32_t& step = plan.relieved[{layer, index}]; step < std::size(candidates);) {
      Vec3 axis = candidates[step++];
      if (core::dot(axis, n) < std::cos(toolpath::kMaxTiltRad) || core::norm(axis - core::normalized(p->tool_axis)) < 1e-3) continue;
      if (!detail::guard_axis(machine, plan.build_model, reach, options.head_clearance_mm, options.retract_mm, p->position_mm, n, axis)) continue;
      if (!turns_clear(axis)) continue;
      p->tool_axis = axis;
      ++turned, ++plan.tilts_eased, ++plan.toolpaths[layer].axes_eased;
      break;
    }
  }
  if (turned == 0) return 0;
  ++plan.relief_rounds;
  plan.layer_reports.clear();
  plan.unsupported_area_mm2 = 0.0;
  detail::check_support(plan, process);
  const verify::DepositCheck deposit(plan.build_model, detail::planned_points(plan), process.bead_width_mm);
  finish_program(plan, machine, process, options, deposit);
  return turned;
}

}  // namespace polyaxis::planner
