#include "polyaxis/report/plan_view.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/motion/kinematics.h"

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
void fill_rotary_ranges(const motion::MachineConfig& machine, const std::vector<machine::ProgramPoint>& program,
                        std::vector<ViewLayer>& layers) {
  if (!motion::has_rotary_axes(machine.kind)) return;
  std::vector<bool> seen(layers.size(), false);
  std::optional<motion::MachinePose> previous;
  for (const machine::ProgramPoint& p : program) {
    auto pose = motion::inverse(machine, p.tip_part_mm, p.tool_axis_part, previous ? &*previous : nullptr);
    if (!pose) continue;
    previous = pose.value();
    if (p.layer >= layers.size()) continue;
    widen(layers[p.layer].tilt_deg, pose.value().a_or_b_deg, !seen[p.layer]);
    widen(layers[p.layer].c_deg, pose.value().c_deg, !seen[p.layer]);
    seen[p.layer] = true;
  }
}

// JSON writing: numbers with fixed decimals, so the same plan gives the same bytes.
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

// Reading.
using Json = nlohmann::ordered_json;  // keeps report.json's key order

Vec3 get_vec(const Json& j) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error("expected [x, y, z]");
  const Vec3 v{j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  if (!core::is_finite(v)) throw std::runtime_error("a coordinate is not finite");
  return v;
}

std::vector<Vec3> get_flat(const Json& j) {
  if (!j.is_array() || j.size() % 3 != 0) throw std::runtime_error("a point list is not a multiple of 3 numbers");
  std::vector<Vec3> out(j.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = {j[3 * i].get<double>(), j[3 * i + 1].get<double>(), j[3 * i + 2].get<double>()};
    if (!core::is_finite(out[i])) throw std::runtime_error("a coordinate is not finite");
  }
  return out;
}

std::vector<std::vector<Vec3>> get_rings(const Json& j) {
  std::vector<std::vector<Vec3>> out;
  for (const Json& ring : j) out.push_back(get_flat(ring));
  return out;
}

std::array<double, 2> get_range(const Json& j) {
  if (!j.is_array() || j.size() != 2) throw std::runtime_error("expected [min, max]");
  return {j[0].get<double>(), j[1].get<double>()};
}

std::vector<machine::ProgramPoint> program_rows(const Json& rows) {
  std::vector<machine::ProgramPoint> program;
  if (!rows.is_array()) throw std::runtime_error("\"program\" is not an array");
  program.reserve(rows.size());
  for (const Json& row : rows) {
    if (!row.is_array() || row.size() != 10) throw std::runtime_error("a program row is not 10 numbers");
    machine::ProgramPoint p;
    p.tip_part_mm = {row[0].get<double>(), row[1].get<double>(), row[2].get<double>()};
    p.tool_axis_part = {row[3].get<double>(), row[4].get<double>(), row[5].get<double>()};
    p.feed_mm_s = row[6].get<double>();
    p.process_on = row[7].get<int>() != 0;
    p.layer = row[8].get<std::uint32_t>();
    p.region = row[9].get<std::uint32_t>();
    if (!core::is_finite(p.tip_part_mm) || !core::is_finite(p.tool_axis_part) || !std::isfinite(p.feed_mm_s)) {
      throw std::runtime_error("a program row is not finite");
    }
    program.push_back(std::move(p));
  }
  return program;
}

}  // namespace

std::string metrics_object(std::string_view metrics_json) {
  if (metrics_json.empty()) return "{}";
  const auto doc = nlohmann::ordered_json::parse(metrics_json, nullptr, false);
  return doc.is_object() ? doc.dump(2) : std::string("{}");
}

PlanView make_plan_view(const planner::Plan& plan, const motion::MachineConfig& machine, const motion::ProcessConfig& process,
                        const analysis::CentroidalAxis* axis, std::string part, std::string metrics_json) {
  PlanView view;
  view.part = std::move(part);
  view.machine = machine.name;
  view.kinematics = std::string(motion::kinematics_name(machine.kind));
  if (motion::has_rotary_axes(machine.kind)) view.tilt_axis = std::string(1, motion::tilt_axis_letter(machine.kind));
  view.process = process.name;
  view.bead_width_mm = process.bead_width_mm;
  view.placement_mm = plan.placement_mm;
  view.metrics_json = std::move(metrics_json);
  view.regions = plan.placed_regions;
  if (axis != nullptr) {
    ViewAxis a;
    for (const analysis::AxisNode& n : axis->nodes) a.nodes.push_back(n.position + plan.placement_mm);
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
    v.area_mm2 = l.area_mm2;
    v.unsupported_area_mm2 = r.unsupported_area_mm2;
    v.max_tilt_deg = r.max_tilt_deg;
    v.paths = r.paths;
    add_rings(l.polygons, l.frame, v.contours);
    add_rings(r.unsupported, l.frame, v.unsupported);
  }
  view.program = plan.program;
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
  fmt::format_to(std::back_inserter(out), ",\"bead_width_mm\":{:.6f},\"placement_mm\":", view.bead_width_mm);
  put_vec(out, view.placement_mm);
  out += ",\n\"report\":";
  out += metrics_object(view.metrics_json);
  out += ",\n\"regions\":[";
  for (std::size_t i = 0; i < view.regions.size(); ++i) {
    const planner::PlanRegion& r = view.regions[i];
    fmt::format_to(std::back_inserter(out), "{}\n{{\"id\":{},\"parent\":{},\"build_direction\":", i ? "," : "", r.id,
                   r.parent ? fmt::to_string(*r.parent) : std::string("null"));
    put_vec(out, core::normalized(r.direction), 9);
    out += ",\"base_point\":", put_vec(out, r.base_point);
    fmt::format_to(std::back_inserter(out), ",\"support_free\":{},\"volume_mm3\":{:.3f},\"vertices\":", r.support_free,
                   mesh::signed_volume(r.mesh));
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
                   ",\"thickness_mm\":{:.6f},\"area_mm2\":{:.6f},\"unsupported_area_mm2\":{:.6f},\"max_tilt_deg\":{:.6f},\"paths\":{},"
                   "\"tilt_deg\":[{:.6f},{:.6f}],\"c_deg\":[{:.6f},{:.6f}],\"contours\":",
                   l.thickness_mm, l.area_mm2, l.unsupported_area_mm2, l.max_tilt_deg, l.paths, l.tilt_deg[0], l.tilt_deg[1],
                   l.c_deg[0], l.c_deg[1]);
    put_rings(out, l.contours);
    out += ",\"unsupported\":";
    put_rings(out, l.unsupported);
    out += '}';
  }
  out += "],\n\"program\":[\n";
  for (std::size_t i = 0; i < view.program.size(); ++i) {
    const machine::ProgramPoint& p = view.program[i];
    fmt::format_to(std::back_inserter(out), "{}[{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.6g},{},{},{}]", i ? ",\n" : "",
                   p.tip_part_mm.x, p.tip_part_mm.y, p.tip_part_mm.z, p.tool_axis_part.x, p.tool_axis_part.y, p.tool_axis_part.z,
                   p.feed_mm_s, p.process_on ? 1 : 0, p.layer, p.region);
  }
  out += "\n]}\n";
  return out;
}

core::Result<std::vector<machine::ProgramPoint>> read_plan_program(std::string_view json, const std::string& source) {
  try {
    return program_rows(Json::parse(json).at("program"));
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInvalidInput, fmt::format("{}: not a polyaxis plan: {}", source, e.what()));
  }
}

core::Result<PlanView> read_plan_view(std::string_view json, const std::string& source) {
  PlanView view;
  try {
    const Json doc = Json::parse(json);
    if (doc.value("format", std::string()) != "polyaxis-plan/1") throw std::runtime_error("\"format\" is not \"polyaxis-plan/1\"");
    view.part = doc.at("part").get<std::string>();
    view.machine = doc.at("machine").get<std::string>();
    view.kinematics = doc.at("kinematics").get<std::string>();
    view.tilt_axis = doc.at("tilt_axis").get<std::string>();
    view.process = doc.at("process").get<std::string>();
    view.bead_width_mm = doc.at("bead_width_mm").get<double>();
    if (!std::isfinite(view.bead_width_mm)) throw std::runtime_error("bead_width_mm is not finite");
    view.placement_mm = get_vec(doc.at("placement_mm"));
    if (!doc.at("report").is_object()) throw std::runtime_error("\"report\" is not an object");
    view.metrics_json = doc.at("report").dump(2);
    for (const Json& r : doc.at("regions")) {
      planner::PlanRegion region;
      region.id = r.at("id").get<std::uint32_t>();
      if (!r.at("parent").is_null()) region.parent = r.at("parent").get<std::uint32_t>();
      region.direction = get_vec(r.at("build_direction"));
      region.base_point = get_vec(r.at("base_point"));
      region.support_free = r.at("support_free").get<bool>();
      region.mesh.vertices = get_flat(r.at("vertices"));
      const Json& tris = r.at("triangles");
      if (!tris.is_array() || tris.size() % 3 != 0) throw std::runtime_error("a triangle list is not a multiple of 3 indices");
      for (std::size_t i = 0; i < tris.size(); i += 3) {
        const std::array<std::uint32_t, 3> t{tris[i].get<std::uint32_t>(), tris[i + 1].get<std::uint32_t>(), tris[i + 2].get<std::uint32_t>()};
        for (std::uint32_t c : t) {
          if (c >= region.mesh.vertices.size()) throw std::runtime_error(fmt::format("region {}: a vertex index is out of range", region.id));
        }
        region.mesh.triangles.push_back(t);
      }
      view.regions.push_back(std::move(region));
    }
    if (!doc.at("axis").is_null()) {
      ViewAxis axis;
      for (const Json& n : doc.at("axis").at("nodes")) axis.nodes.push_back(get_vec(n));
      for (const Json& l : doc.at("axis").at("links")) {
        if (!l.is_array() || l.size() != 3) throw std::runtime_error("an axis link is not [from, to, break]");
        const std::array<std::uint32_t, 3> link{l[0].get<std::uint32_t>(), l[1].get<std::uint32_t>(), l[2].get<std::uint32_t>()};
        if (link[0] >= axis.nodes.size() || link[1] >= axis.nodes.size()) throw std::runtime_error("an axis link's node is out of range");
        axis.links.push_back(link);
      }
      view.axis = std::move(axis);
    }
    for (const Json& l : doc.at("layers")) {
      ViewLayer layer;
      layer.index = l.at("index").get<std::uint32_t>();
      layer.region = l.at("region").get<std::uint32_t>();
      layer.origin = get_vec(l.at("origin"));
      layer.normal = get_vec(l.at("normal"));
      layer.u = get_vec(l.at("u"));
      layer.v = get_vec(l.at("v"));
      layer.thickness_mm = l.at("thickness_mm").get<double>();
      layer.area_mm2 = l.at("area_mm2").get<double>();
      layer.unsupported_area_mm2 = l.at("unsupported_area_mm2").get<double>();
      layer.max_tilt_deg = l.at("max_tilt_deg").get<double>();
      layer.paths = l.at("paths").get<std::uint32_t>();
      layer.tilt_deg = get_range(l.at("tilt_deg"));
      layer.c_deg = get_range(l.at("c_deg"));
      layer.contours = get_rings(l.at("contours"));
      layer.unsupported = get_rings(l.at("unsupported"));
      for (double x : {layer.thickness_mm, layer.area_mm2, layer.unsupported_area_mm2, layer.max_tilt_deg, layer.tilt_deg[0],
                       layer.tilt_deg[1], layer.c_deg[0], layer.c_deg[1]}) {
        if (!std::isfinite(x)) throw std::runtime_error(fmt::format("layer {}: a number is not finite", layer.index));
      }
      view.layers.push_back(std::move(layer));
    }
    view.program = program_rows(doc.at("program"));
    for (const machine::ProgramPoint& p : view.program) {
      if (p.layer >= view.layers.size()) throw std::runtime_error("a program row's layer is out of range");
    }
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInvalidInput, fmt::format("{}: not a polyaxis plan: {}", source, e.what()));
  }
  return view;
}

}  // namespace polyaxis::report
