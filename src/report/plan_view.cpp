#include "polyaxis/report/plan_view.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/machine/kinematics.h"

namespace polyaxis::report {
namespace {

std::vector<Vec3> ring_in_world(const geom2d::Ring& ring, const slicing::Frame& frame) {
  std::vector<Vec3> out;
  out.reserve(ring.size());
  for (const geom2d::Point& p : ring) out.push_back(frame.to_world(geom2d::to_mm(p.x), geom2d::to_mm(p.y)));
  return out;
}

void add_rings(const std::vector<geom2d::Polygon>& polygons, const slicing::Frame& frame, std::vector<std::vector<Vec3>>& out) {
  for (const geom2d::Polygon& poly : polygons) {
    out.push_back(ring_in_world(poly.outer, frame));
    for (const geom2d::Ring& hole : poly.holes) out.push_back(ring_in_world(hole, frame));
  }
}

void widen(std::array<double, 2>& range, double value, bool first) {
  if (first) range = {value, value};
  range[0] = std::min(range[0], value), range[1] = std::max(range[1], value);
}

// Rotary positions per layer, solved along the program as the G-code writer solves them (each
// pose from the previous one). Points the machine cannot reach leave their layer's range alone:
// the G-code writer reports them.
void fill_rotary_ranges(const machine::MachineConfig& machine, const std::vector<post::ProgramPoint>& program,
                        std::vector<ViewLayer>& layers) {
  if (!machine::has_rotary_axes(machine.kind)) return;
  std::vector<bool> seen(layers.size(), false);
  std::optional<machine::MachinePose> previous;
  for (const post::ProgramPoint& p : program) {
    auto pose = machine::inverse(machine, p.tip_part_mm, p.tool_axis_part, previous ? &*previous : nullptr);
    if (!pose) continue;
    previous = pose.value();
    if (p.layer >= layers.size()) continue;
    widen(layers[p.layer].tilt_deg, pose.value().a_or_b_deg, !seen[p.layer]);
    widen(layers[p.layer].c_deg, pose.value().c_deg, !seen[p.layer]);
    seen[p.layer] = true;
  }
}

// JSON writing: numbers with fixed decimals, so the same plan gives the same bytes.
std::string build_model_json(const machine::BuildModel& m) {
  nlohmann::ordered_json j;
  j["nozzle"] = {{"tip_half_angle_deg", m.nozzle.tip_half_angle_deg},
                 {"cone_height_mm", m.nozzle.cone_height_mm},
                 {"cylinder_radius_mm", m.nozzle.cylinder_radius_mm},
                 {"cylinder_height_mm", m.nozzle.cylinder_height_mm}};
  nlohmann::ordered_json boxes = nlohmann::ordered_json::array();
  for (const machine::HeadBox& b : m.head_boxes) {
    boxes.push_back({{"min_mm", {b.min_mm[0], b.min_mm[1], b.min_mm[2]}}, {"max_mm", {b.max_mm[0], b.max_mm[1], b.max_mm[2]}}});
  }
  j["head_boxes"] = std::move(boxes);
  j["table_radius_mm"] = m.table_radius_mm;
  j["table_centre_mm"] = {m.table_centre_mm.x, m.table_centre_mm.y, m.table_centre_mm.z};
  const machine::SubstratePlate& p = m.substrate;
  j["substrate"] = {{"x_mm", {p.x_min_mm, p.x_max_mm}}, {"y_mm", {p.y_min_mm, p.y_max_mm}}, {"top_z_mm", p.top_z_mm}, {"thickness_mm", p.thickness_mm}};
  return j.dump();
}

void put_vec(std::string& out, Vec3 v, int decimals = 6) {
  fmt::format_to(std::back_inserter(out), "[{:.{}f},{:.{}f},{:.{}f}]", v.x, decimals, v.y, decimals, v.z, decimals);
}

void put_flat(std::string& out, const std::vector<Vec3>& points) {
  out += '[';
  for (std::size_t i = 0; i < points.size(); ++i) {
    fmt::format_to(std::back_inserter(out), "{}{:.6f},{:.6f},{:.6f}", i ? "," : "", points[i].x, points[i].y, points[i].z);
  }
  out += ']';
}

void put_rings(std::string& out, const std::vector<std::vector<Vec3>>& rings) {
  out += '[';
  for (std::size_t i = 0; i < rings.size(); ++i) {
    if (i) out += ',';
    put_flat(out, rings[i]);
  }
  out += ']';
}

void put_string(std::string& out, const std::string& s) { out += nlohmann::json(s).dump(); }

}  // namespace

std::string metrics_object(std::string_view metrics_json) {
  if (metrics_json.empty()) return "{}";
  const auto doc = nlohmann::ordered_json::parse(metrics_json, nullptr, false);
  return doc.is_object() ? doc.dump(2) : std::string("{}");
}

PlanView make_plan_view(const planner::Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                        const analysis::CentroidalAxis* axis, std::string part, std::string metrics_json,
                        const verify::BuildCheck* check) {
  PlanView view;
  if (check != nullptr) {
    for (const verify::Collision& c : check->collision_list) {
      view.collisions.push_back({c.tip,
                                 fmt::format("layer {} region {}, line {}: the head strikes the {} ({:.2f} mm)", c.layer, c.region, c.line,
                                             c.body, c.depth_mm),
                                 c.line});
    }
  }
  view.part = std::move(part);
  view.machine = machine.name;
  view.kinematics = std::string(machine::kinematics_name(machine.kind));
  if (machine::has_rotary_axes(machine.kind)) view.tilt_axis = std::string(1, machine::tilt_axis_letter(machine.kind));
  view.process = process.name;
  view.bead_width_mm = process.bead_width_mm;
  view.placement = plan.placement;
  view.metrics_json = std::move(metrics_json);
  view.regions = plan.placed_regions;
  if (axis != nullptr) {
    ViewAxis a;
    for (const analysis::AxisNode& n : axis->nodes) a.nodes.push_back(plan.placement.apply(n.position));
    for (const analysis::AxisLink& l : axis->links) a.links.push_back({l.from, l.to, l.is_break ? 1u : 0u});
    view.axis = std::move(a);
  }
  const auto& layers = plan.layers.layers;
  view.layers.resize(layers.size());
  for (std::size_t k = 0; k < layers.size(); ++k) {
    const slicing::Layer& l = layers[k];
    const planner::LayerReport& r = plan.layer_reports[k];
    ViewLayer& v = view.layers[k];
    v.index = l.index;
    v.region = r.region;
    v.origin = l.frame.origin, v.u = l.frame.u, v.v = l.frame.v, v.normal = l.frame.d;
    v.thickness_mm = l.thickness_mm();
    v.thickness_range_mm = {r.min_thickness_mm, r.max_thickness_mm};
    v.area_mm2 = l.area_mm2;
    v.unsupported_area_mm2 = r.unsupported_area_mm2;
    v.max_tilt_deg = r.max_tilt_deg;
    v.paths = r.paths;
    if (k < plan.order.size()) v.order = plan.order[k];
    v.tilt_rule = r.tilt_rule, v.tilted_points = r.tilted_points, v.turned_points = r.turned_points, v.eased_points = r.eased_points;
    if (l.conformal) {
      v.contours = l.conformal->contours;  // on the curved layer
    } else {
      add_rings(l.polygons, l.frame, v.contours);
    }
    add_rings(r.unsupported, l.frame, v.unsupported);
    if (k < plan.toolpaths.size()) {
      for (const toolpath::ThinRegion& t : plan.toolpaths[k].thin) v.thin.push_back({t.where_mm, t.area_mm2, t.what});
    }
  }
  view.program = plan.program;
  view.rules = planner::rule_base(machine, process, plan);
  view.reorientations = plan.reorientation_list;
  view.build_model = plan.build_model;
  fill_rotary_ranges(machine, view.program, view.layers);
  return view;
}

std::string plan_view_json(const PlanView& view) {
  std::string out = "{\"format\":\"polyaxis-plan/1\",\n\"part\":";
  put_string(out, view.part);
  out += ",\"machine\":", put_string(out, view.machine);
  out += ",\"kinematics\":", put_string(out, view.kinematics);
  out += ",\"tilt_axis\":", put_string(out, view.tilt_axis);
  out += ",\"process\":", put_string(out, view.process);
  fmt::format_to(std::back_inserter(out), ",\"bead_width_mm\":{:.6f},\"placement_rotation\":[", view.bead_width_mm);
  for (int i = 0; i < 3; ++i) {
    if (i) out += ',';
    put_vec(out, view.placement.rows[i], 12);
  }
  out += "],\"placement_mm\":";
  put_vec(out, view.placement.translation_mm);
  out += ",\n\"report\":";
  out += metrics_object(view.metrics_json);
  out += ",\n\"regions\":[";
  for (std::size_t i = 0; i < view.regions.size(); ++i) {
    const planner::PlanRegion& r = view.regions[i];
    fmt::format_to(std::back_inserter(out), "{}\n{{\"id\":{},\"parent\":{},\"build_direction\":", i ? "," : "", r.id,
                   r.parent ? fmt::to_string(*r.parent) : std::string("null"));
    put_vec(out, core::normalized(r.direction), 9);
    out += ",\"base_point\":", put_vec(out, r.base_point);
    fmt::format_to(std::back_inserter(out), ",\"support_free\":{},\"volume_mm3\":{:.3f},\"overhang_mm2\":{:.3f},\"rule\":{},\"rests_on\":{},",
                   r.support_free, mesh::signed_volume(r.mesh), r.overhang_mm2, nlohmann::json(r.rule).dump(), nlohmann::json(r.rests_on).dump());
    fmt::format_to(std::back_inserter(out), "\"layers\":{{\"strategy\":\"{}\",\"rule\":{},\"why\":{}}},\"prebuilt\":{},",
                   slicing::layer_strategy_name(r.layers), nlohmann::json(r.layers_rule).dump(), nlohmann::json(r.layers_why).dump(), r.prebuilt);
    if (!r.direction_rule.empty()) {
      fmt::format_to(std::back_inserter(out), "\"direction\":{{\"rule\":{},\"why\":{}}},", nlohmann::json(r.direction_rule).dump(),
                     nlohmann::json(r.direction_why).dump());
    }
    out += "\"vertices\":";
    put_flat(out, r.mesh.vertices);
    out += ",\"triangles\":[";
    for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
      const auto& tri = r.mesh.triangles[t];
      fmt::format_to(std::back_inserter(out), "{}{},{},{}", t ? "," : "", tri[0], tri[1], tri[2]);
    }
    out += "]}";
  }
  out += "],\n\"axis\":";
  if (!view.axis) {
    out += "null";
  } else {
    out += "{\"nodes\":[";
    for (std::size_t i = 0; i < view.axis->nodes.size(); ++i) {
      if (i) out += ',';
      put_vec(out, view.axis->nodes[i]);
    }
    out += "],\"links\":[";
    for (std::size_t i = 0; i < view.axis->links.size(); ++i) {
      const auto& l = view.axis->links[i];
      fmt::format_to(std::back_inserter(out), "{}[{},{},{}]", i ? "," : "", l[0], l[1], l[2]);
    }
    out += "]}";
  }
  out += ",\n\"layers\":[";
  for (std::size_t k = 0; k < view.layers.size(); ++k) {
    const ViewLayer& l = view.layers[k];
    fmt::format_to(std::back_inserter(out), "{}\n{{\"index\":{},\"region\":{},\"origin\":", k ? "," : "", l.index, l.region);
    put_vec(out, l.origin);
    out += ",\"normal\":", put_vec(out, l.normal, 9);
    out += ",\"u\":", put_vec(out, l.u, 9);
    out += ",\"v\":", put_vec(out, l.v, 9);
    fmt::format_to(std::back_inserter(out),
                   ",\"thickness_mm\":{:.6f},\"thickness_range_mm\":[{:.6f},{:.6f}],\"area_mm2\":{:.6f},\"unsupported_area_mm2\":{:.6f},"
                   "\"max_tilt_deg\":{:.6f},\"paths\":{},\"tilt_deg\":[{:.6f},{:.6f}],\"c_deg\":[{:.6f},{:.6f}]",
                   l.thickness_mm, l.thickness_range_mm[0], l.thickness_range_mm[1], l.area_mm2, l.unsupported_area_mm2, l.max_tilt_deg, l.paths, l.tilt_deg[0], l.tilt_deg[1],
                   l.c_deg[0], l.c_deg[1]);
    fmt::format_to(std::back_inserter(out), ",\"order\":{{\"region_layer\":{},\"level\":{},\"rule\":{},\"interferes_with\":{},\"interferences\":{}}}",
                   l.order.region_layer, l.order.level, nlohmann::json(l.order.rule).dump(), nlohmann::json(l.order.interferes_with).dump(),
                   l.order.interferences);
    fmt::format_to(std::back_inserter(out), ",\"tilt\":{{\"rule\":{},\"tilted_points\":{},\"turned_points\":{},\"eased_points\":{}}}",
                   nlohmann::json(l.tilt_rule).dump(), l.tilted_points, l.turned_points, l.eased_points);
    out += ",\"contours\":";
    put_rings(out, l.contours);
    out += ",\"unsupported\":";
    put_rings(out, l.unsupported);
    out += ",\"thin\":[";
    for (std::size_t i = 0; i < l.thin.size(); ++i) {
      out += i ? ",{\"where\":" : "{\"where\":";
      put_vec(out, l.thin[i].where);
      fmt::format_to(std::back_inserter(out), ",\"area_mm2\":{:.6f},\"what\":", l.thin[i].area_mm2);
      put_string(out, l.thin[i].what);
      out += '}';
    }
    out += "]}";
  }
  out += "],\n\"program\":[\n";
  for (std::size_t i = 0; i < view.program.size(); ++i) {
    const post::ProgramPoint& p = view.program[i];
    fmt::format_to(std::back_inserter(out), "{}[{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.6g},{},{},{}]", i ? ",\n" : "",
                   p.tip_part_mm.x, p.tip_part_mm.y, p.tip_part_mm.z, p.tool_axis_part.x, p.tool_axis_part.y, p.tool_axis_part.z,
                   p.feed_mm_s, p.process_on ? 1 : 0, p.layer, p.region);
  }
  out += "\n],\n\"collisions\":[";
  for (std::size_t i = 0; i < view.collisions.size(); ++i) {
    out += i ? ",\n{\"position\":" : "\n{\"position\":";
    put_vec(out, view.collisions[i].position);
    out += ",\"what\":" + nlohmann::json(view.collisions[i].what).dump() + fmt::format(",\"line\":{}}}", view.collisions[i].line);
  }
  out += "],\n\"rules\":[";
  for (std::size_t i = 0; i < view.rules.size(); ++i) {
    const planner::Rule& r = view.rules[i];
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [key, value] : r.parameters) params[key] = value;
    fmt::format_to(std::back_inserter(out), "{}\n{{\"id\":{},\"says\":{},\"parameters\":{}}}", i ? "," : "", nlohmann::json(r.id).dump(),
                   nlohmann::json(r.says).dump(), params.dump());
  }
  out += "],\n\"reorientations\":[";
  for (std::size_t i = 0; i < view.reorientations.size(); ++i) {
    const planner::Reorientation& r = view.reorientations[i];
    fmt::format_to(std::back_inserter(out), "{}\n{{\"point\":{},\"layer\":{},\"angle_deg\":{:.3f},\"rule\":{}}}", i ? "," : "", r.point, r.layer,
                   r.angle_deg, nlohmann::json(r.rule).dump());
  }
  out += "],\n\"head\":";
  out += build_model_json(view.build_model);
  out += "}\n";
  return out;
}

}  // namespace polyaxis::report
