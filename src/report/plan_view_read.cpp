// Reading plan.json back (plan_view.h): kept apart from the writer so the fuzz target
// (tests/fuzz/fuzz_plan_json.cpp) links only this.
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "polyaxis/core/json_depth.h"
#include "polyaxis/report/plan_view.h"

namespace polyaxis::report {
namespace {

using Json = nlohmann::ordered_json;  // keeps report.json's key order

// An id, index or count: a JSON integer from 0 to 2³² − 1. (nlohmann's get<std::uint32_t>() of a
// negative or fractional number is undefined behaviour: fuzz_plan_json found -24.9995.)
std::uint32_t get_u32(const Json& j) {
  if (!j.is_number_unsigned() || j.get<std::uint64_t>() > UINT32_MAX) throw std::runtime_error("expected an integer from 0 to 4294967295");
  return static_cast<std::uint32_t>(j.get<std::uint64_t>());
}

// A flag: a JSON integer, true when non-zero.
bool get_flag(const Json& j) {
  if (!j.is_number_integer()) throw std::runtime_error("expected an integer flag");
  return j.get<std::int64_t>() != 0;
}

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

double get_finite(const Json& j) {
  const double x = j.get<double>();
  if (!std::isfinite(x)) throw std::runtime_error("a number is not finite");
  return x;
}

// The build model's prebuilt body from the regions marked prebuilt (plan.json keeps their meshes,
// not the samples). A fuzzed plan must not make a reader run out of memory: a surface that needs
// more than machine::kMaxPrebuiltSamples samples at the bead's spacing is refused.
void add_prebuilt_regions(PlanView& view) {
  const double spacing = machine::kPrebuiltSpacingBeads * view.bead_width_mm;
  for (const planner::PlanRegion& r : view.regions) {
    if (!r.prebuilt) continue;
    if (!(spacing > 0.0) || !machine::add_prebuilt(view.build_model.prebuilt, r.mesh.vertices, r.mesh.triangles, spacing)) {
      throw std::runtime_error(fmt::format("prebuilt region {}: its surface is too large for the bead width", r.id));
    }
  }
}

machine::BuildModel get_build_model(const Json& j) {
  machine::BuildModel m;
  const Json& n = j.at("nozzle");
  m.nozzle.tip_half_angle_deg = get_finite(n.at("tip_half_angle_deg"));
  m.nozzle.cone_height_mm = get_finite(n.at("cone_height_mm"));
  m.nozzle.cylinder_radius_mm = get_finite(n.at("cylinder_radius_mm"));
  m.nozzle.cylinder_height_mm = get_finite(n.at("cylinder_height_mm"));
  for (const Json& b : j.at("head_boxes")) {
    machine::HeadBox box;
    const Vec3 lo = get_vec(b.at("min_mm")), hi = get_vec(b.at("max_mm"));
    box.min_mm[0] = lo.x, box.min_mm[1] = lo.y, box.min_mm[2] = lo.z;
    box.max_mm[0] = hi.x, box.max_mm[1] = hi.y, box.max_mm[2] = hi.z;
    m.head_boxes.push_back(box);
  }
  m.table_radius_mm = get_finite(j.at("table_radius_mm"));
  m.table_centre_mm = get_vec(j.at("table_centre_mm"));
  const Json& p = j.at("substrate");
  const auto x = get_range(p.at("x_mm")), y = get_range(p.at("y_mm"));
  m.substrate.x_min_mm = x[0], m.substrate.x_max_mm = x[1], m.substrate.y_min_mm = y[0], m.substrate.y_max_mm = y[1];
  m.substrate.top_z_mm = get_finite(p.at("top_z_mm"));
  m.substrate.thickness_mm = get_finite(p.at("thickness_mm"));
  return m;
}

std::vector<post::ProgramPoint> program_rows(const Json& rows) {
  std::vector<post::ProgramPoint> program;
  if (!rows.is_array()) throw std::runtime_error("\"program\" is not an array");
  program.reserve(rows.size());
  for (const Json& row : rows) {
    if (!row.is_array() || row.size() != 10) throw std::runtime_error("a program row is not 10 numbers");
    post::ProgramPoint p;
    p.tip_part_mm = {row[0].get<double>(), row[1].get<double>(), row[2].get<double>()};
    p.tool_axis_part = {row[3].get<double>(), row[4].get<double>(), row[5].get<double>()};
    p.feed_mm_s = row[6].get<double>();
    p.process_on = get_flag(row[7]);
    p.layer = get_u32(row[8]);
    p.region = get_u32(row[9]);
    if (!core::is_finite(p.tip_part_mm) || !core::is_finite(p.tool_axis_part) || !std::isfinite(p.feed_mm_s)) {
      throw std::runtime_error("a program row is not finite");
    }
    program.push_back(std::move(p));
  }
  return program;
}

void too_deep(std::string_view json) {
  if (const auto at = core::json_too_deep(json)) {
    throw std::runtime_error(fmt::format("nested deeper than {} levels at byte {}", core::kMaxJsonDepth, *at));
  }
}

}  // namespace

core::Result<std::vector<post::ProgramPoint>> read_plan_program(std::string_view json, const std::string& source) {
  try {
    too_deep(json);
    return program_rows(Json::parse(json).at("program"));
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInvalidInput, fmt::format("{}: not a polyaxis plan: {}", source, e.what()));
  }
}

core::Result<PlanView> read_plan_view(std::string_view json, const std::string& source) {
  PlanView view;
  try {
    too_deep(json);
    const Json doc = Json::parse(json);
    if (doc.value("format", std::string()) != "polyaxis-plan/1") throw std::runtime_error("\"format\" is not \"polyaxis-plan/1\"");
    view.part = doc.at("part").get<std::string>();
    view.machine = doc.at("machine").get<std::string>();
    view.kinematics = doc.at("kinematics").get<std::string>();
    view.tilt_axis = doc.at("tilt_axis").get<std::string>();
    view.process = doc.at("process").get<std::string>();
    view.bead_width_mm = doc.at("bead_width_mm").get<double>();
    if (!std::isfinite(view.bead_width_mm)) throw std::runtime_error("bead_width_mm is not finite");
    const Json& rows = doc.at("placement_rotation");
    if (!rows.is_array() || rows.size() != 3) throw std::runtime_error("placement_rotation is not three rows");
    for (std::size_t i = 0; i < 3; ++i) view.placement.rows[i] = get_vec(rows[i]);
    view.placement.translation_mm = get_vec(doc.at("placement_mm"));
    if (!doc.at("report").is_object()) throw std::runtime_error("\"report\" is not an object");
    view.metrics_json = doc.at("report").dump(2);
    for (const Json& r : doc.at("regions")) {
      planner::PlanRegion region;
      region.id = get_u32(r.at("id"));
      if (!r.at("parent").is_null()) region.parent = get_u32(r.at("parent"));
      region.direction = get_vec(r.at("build_direction"));
      region.base_point = get_vec(r.at("base_point"));
      region.support_free = r.at("support_free").get<bool>();
      if (r.contains("rule")) {  // plans written before the rule base have none
        region.rule = r.at("rule").get<std::string>();
        region.rests_on = r.at("rests_on").get<std::vector<std::uint32_t>>();
        region.volume_mm3 = get_finite(r.at("volume_mm3"));
        region.overhang_mm2 = get_finite(r.at("overhang_mm2"));
      }
      if (r.contains("layers")) {  // plans written before tilted layers have none
        const Json& l = r.at("layers");
        const std::string strategy = l.at("strategy").get<std::string>();
        if (strategy != "planar" && strategy != "tilted" && strategy != "conformal") {
          throw std::runtime_error(fmt::format("region {}: unknown layer strategy '{}'", region.id, strategy));
        }
        region.layers = strategy == "tilted"      ? slicing::LayerStrategy::kTilted
                        : strategy == "conformal" ? slicing::LayerStrategy::kConformal
                                                  : slicing::LayerStrategy::kPlanar;
        region.layers_rule = l.at("rule").get<std::string>();
        region.layers_why = l.at("why").get<std::string>();
      }
      if (r.contains("prebuilt")) region.prebuilt = r.at("prebuilt").get<bool>();  // plans written before --substrate have none
      if (r.contains("direction")) {  // plans written before redirected regions have none
        region.direction_rule = r.at("direction").at("rule").get<std::string>();
        region.direction_why = r.at("direction").at("why").get<std::string>();
      }
      region.mesh.vertices = get_flat(r.at("vertices"));
      const Json& tris = r.at("triangles");
      if (!tris.is_array() || tris.size() % 3 != 0) throw std::runtime_error("a triangle list is not a multiple of 3 indices");
      for (std::size_t i = 0; i < tris.size(); i += 3) {
        const std::array<std::uint32_t, 3> t{get_u32(tris[i]), get_u32(tris[i + 1]), get_u32(tris[i + 2])};
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
        const std::array<std::uint32_t, 3> link{get_u32(l[0]), get_u32(l[1]), get_u32(l[2])};
        if (link[0] >= axis.nodes.size() || link[1] >= axis.nodes.size()) throw std::runtime_error("an axis link's node is out of range");
        axis.links.push_back(link);
      }
      view.axis = std::move(axis);
    }
    for (const Json& l : doc.at("layers")) {
      ViewLayer layer;
      layer.index = get_u32(l.at("index"));
      layer.region = get_u32(l.at("region"));
      layer.origin = get_vec(l.at("origin"));
      layer.normal = get_vec(l.at("normal"));
      layer.u = get_vec(l.at("u"));
      layer.v = get_vec(l.at("v"));
      layer.thickness_mm = l.at("thickness_mm").get<double>();
      if (l.contains("thickness_range_mm")) {
        const Json& range = l.at("thickness_range_mm");
        if (!range.is_array() || range.size() != 2) throw std::runtime_error("\"thickness_range_mm\" is not a pair");
        layer.thickness_range_mm = {get_finite(range[0]), get_finite(range[1])};
      } else {
        layer.thickness_range_mm = {layer.thickness_mm, layer.thickness_mm};
      }
      layer.area_mm2 = l.at("area_mm2").get<double>();
      layer.unsupported_area_mm2 = l.at("unsupported_area_mm2").get<double>();
      layer.max_tilt_deg = l.at("max_tilt_deg").get<double>();
      layer.paths = get_u32(l.at("paths"));
      layer.tilt_deg = get_range(l.at("tilt_deg"));
      layer.c_deg = get_range(l.at("c_deg"));
      layer.contours = get_rings(l.at("contours"));
      layer.unsupported = get_rings(l.at("unsupported"));
      if (l.contains("thin")) {  // plans written before the thin pieces were listed have none
        for (const Json& t : l.at("thin")) layer.thin.push_back({get_vec(t.at("where")), get_finite(t.at("area_mm2")), t.at("what").get<std::string>()});
      }
      layer.order.region = layer.region;
      if (l.contains("order")) {  // plans written before the layer order was recorded have none
        const Json& o = l.at("order");
        layer.order.region_layer = get_u32(o.at("region_layer"));
        layer.order.level = get_u32(o.at("level"));
        layer.order.rule = o.at("rule").get<std::string>();
        for (const Json& i : o.at("interferes_with")) layer.order.interferes_with.push_back(get_u32(i));
        layer.order.interferences = get_u32(o.at("interferences"));
        const Json& t = l.at("tilt");
        layer.tilt_rule = t.at("rule").get<std::string>();
        layer.tilted_points = get_u32(t.at("tilted_points"));
        layer.turned_points = get_u32(t.at("turned_points"));
        layer.eased_points = get_u32(t.at("eased_points"));
      }
      for (double x : {layer.thickness_mm, layer.area_mm2, layer.unsupported_area_mm2, layer.max_tilt_deg, layer.tilt_deg[0],
                       layer.tilt_deg[1], layer.c_deg[0], layer.c_deg[1]}) {
        if (!std::isfinite(x)) throw std::runtime_error(fmt::format("layer {}: a number is not finite", layer.index));
      }
      view.layers.push_back(std::move(layer));
    }
    view.program = program_rows(doc.at("program"));
    for (const post::ProgramPoint& p : view.program) {
      if (p.layer >= view.layers.size()) throw std::runtime_error("a program row's layer is out of range");
    }
    if (doc.contains("collisions")) {  // plans written before collisions were checked have none
      for (const Json& c : doc.at("collisions")) {
        view.collisions.push_back({get_vec(c.at("position")), c.at("what").get<std::string>(),
                                   c.contains("line") ? c.at("line").get<std::uint64_t>() : 0});
      }
    }
    for (const ViewLayer& l : view.layers) {
      for (const std::uint32_t i : l.order.interferes_with) {
        if (i >= view.layers.size()) throw std::runtime_error(fmt::format("layer {}: an interfering layer is out of range", l.index));
      }
    }
    if (doc.contains("rules")) {
      for (const Json& r : doc.at("rules")) {
        planner::Rule rule{r.at("id").get<std::string>(), r.at("says").get<std::string>(), {}};
        for (const auto& [key, value] : r.at("parameters").items()) rule.parameters.emplace_back(key, get_finite(value));
        view.rules.push_back(std::move(rule));
      }
      for (const Json& r : doc.at("reorientations")) {
        planner::Reorientation o;
        o.point = r.at("point").get<std::uint64_t>();
        o.layer = get_u32(r.at("layer"));
        o.angle_deg = get_finite(r.at("angle_deg"));
        o.rule = r.at("rule").get<std::string>();
        if (o.point >= view.program.size() || o.layer >= view.layers.size()) throw std::runtime_error("a reorientation is out of range");
        view.reorientations.push_back(std::move(o));
      }
      view.build_model = get_build_model(doc.at("head"));
    }
    // Always, so that a plan the reader accepts is one it accepts again as written.
    add_prebuilt_regions(view);
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInvalidInput, fmt::format("{}: not a polyaxis plan: {}", source, e.what()));
  }
  return view;
}

}  // namespace polyaxis::report
