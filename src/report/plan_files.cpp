#include "polyaxis/report/plan_files.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace polyaxis::report {
namespace {

using nlohmann::ordered_json;

ordered_json vec(core::Vec3 v) { return ordered_json::array({v.x, v.y, v.z}); }

}  // namespace

std::string report_json(const planner::Plan& plan, const machine::SimulationReport& sim, const PlanMeta& meta) {
  ordered_json j;
  j["part"] = meta.part;
  j["machine"] = meta.machine;
  j["process"] = meta.process;
  j["gcode"] = meta.gcode;
  j["layers"] = plan.layers.layers.size();
  j["regions"] = plan.regions;
  j["path_length_mm"] = plan.deposit_length_mm + plan.travel_length_mm;
  j["deposit_length_mm"] = plan.deposit_length_mm;
  j["travel_length_mm"] = plan.travel_length_mm;
  // Build time: every G1 block at its programmed feed (deposition, travel and the rotary moves
  // of reorientations, which the controller times by the same F), from the simulation of the
  // written program.
  j["build_time_s"] = sim.feed_time_s;
  j["reorientations"] = plan.reorientations;
  j["support_free"] = plan.unsupported_area_mm2 == 0.0;
  j["unsupported_area_mm2"] = plan.unsupported_area_mm2;
  j["max_tilt_deg"] = plan.max_tilt_deg;
  j["thin_regions"] = plan.thin_regions;
  j["thin_area_mm2"] = plan.thin_area_mm2;
  j["volume_estimate_mm3"] = plan.layers.volume_estimate_mm3;
  j["moves"] = sim.moves;
  j["limit_violations"] = sim.limit_violations;
  j["max_tip_deviation_mm"] = sim.max_tip_deviation_mm;
  j["max_axis_deviation_deg"] = sim.max_axis_deviation_deg;
  j["timings_s"] = {{"read", meta.read_s},           {"repair", meta.repair_s},         {"slice", plan.times.slice_s},
                    {"toolpath", plan.times.toolpath_s}, {"program", plan.times.program_s}, {"support", plan.times.support_s},
                    {"gcode", meta.gcode_s},           {"simulate", meta.simulate_s}};
  j["axis_ranges"] = {{"x", {sim.x_mm.min, sim.x_mm.max}},
                      {"y", {sim.y_mm.min, sim.y_mm.max}},
                      {"z", {sim.z_mm.min, sim.z_mm.max}},
                      {"tilt", {sim.a_or_b_deg.empty() ? 0.0 : sim.a_or_b_deg.min, sim.a_or_b_deg.empty() ? 0.0 : sim.a_or_b_deg.max}},
                      {"c", {sim.c_deg.empty() ? 0.0 : sim.c_deg.min, sim.c_deg.empty() ? 0.0 : sim.c_deg.max}}};
  return j.dump(2) + "\n";
}

std::string plan_json(const planner::Plan& plan, const PlanMeta& meta) {
  std::string out;
  ordered_json head;
  head["part"] = meta.part;
  head["machine"] = meta.machine;
  head["process"] = meta.process;
  head["placement_mm"] = vec(plan.placement_mm);
  ordered_json layers = ordered_json::array();
  for (std::size_t k = 0; k < plan.layers.layers.size(); ++k) {
    const auto& l = plan.layers.layers[k];
    const auto& r = plan.layer_reports[k];
    layers.push_back({{"index", l.index},
                      {"region", r.region},
                      {"origin", vec(l.frame.origin)},
                      {"normal", vec(l.frame.d)},
                      {"thickness_mm", l.thickness_mm()},
                      {"area_mm2", l.area_mm2},
                      {"unsupported_area_mm2", r.unsupported_area_mm2},
                      {"max_tilt_deg", r.max_tilt_deg},
                      {"paths", r.paths}});
  }
  head["layers"] = layers;
  out = head.dump();
  out.pop_back();  // the closing brace: the program follows
  out += ",\n\"program\":[\n";
  for (std::size_t i = 0; i < plan.program.size(); ++i) {
    const machine::ProgramPoint& p = plan.program[i];
    fmt::format_to(std::back_inserter(out), "{}[{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.6g},{},{},{}]", i ? ",\n" : "",
                   p.tip_part_mm.x, p.tip_part_mm.y, p.tip_part_mm.z, p.tool_axis_part.x, p.tool_axis_part.y, p.tool_axis_part.z,
                   p.feed_mm_s, p.process_on ? 1 : 0, p.layer, p.region);
  }
  out += "\n]}\n";
  return out;
}

core::Result<std::vector<machine::ProgramPoint>> read_plan_program(std::string_view json, const std::string& source) {
  std::vector<machine::ProgramPoint> program;
  try {
    const auto doc = nlohmann::json::parse(json);
    const auto& arr = doc.at("program");
    program.reserve(arr.size());
    for (const auto& row : arr) {
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
  } catch (const std::exception& e) {
    return core::make_error(core::ErrorCode::kInvalidInput, fmt::format("{}: not a polyaxis plan: {}", source, e.what()));
  }
  return program;
}

}  // namespace polyaxis::report
