#include "polyaxis/report/plan_files.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace polyaxis::report {
namespace {

using nlohmann::ordered_json;

// The parts of the build time (verify::BuildTime), s.
ordered_json build_time_parts(const verify::BuildTime& t) {
  return {{"deposit", t.deposit_s}, {"travel", t.travel_s}, {"reorientation", t.reorientation_s}, {"dwell", t.dwell_s}};
}

}  // namespace

std::string report_json(const planner::Plan& plan, const verify::SimulationReport& sim, const PlanMeta& meta,
                        const verify::BuildCheck* check) {
  ordered_json j;
  j["part"] = meta.part;
  j["machine"] = meta.machine;
  j["process"] = meta.process;
  j["gcode"] = meta.gcode;
  j["layers"] = plan.layers.layers.size();
  j["regions"] = plan.regions;
  if (!meta.strategy.empty()) j["strategy"] = meta.strategy, j["strategy_reason"] = meta.choice;
  if (!meta.set_id.empty()) j["set_id"] = meta.set_id;
  // Lengths of the tip's path over the part in the program read back (sim): all of it, with the
  // process on, and with it off (travel, approach, retract and transit moves).
  j["path_length_mm"] = sim.path_length_mm;
  j["deposit_length_mm"] = sim.deposit_length_mm;
  j["travel_length_mm"] = sim.path_length_mm - sim.deposit_length_mm;
  // Build time: the written program as LinuxCNC's trajectory planner runs it (accelerations,
  // blending within G64 P, stops at dwells and process switches; verify/simulate.h), with its
  // parts, and the time of the blocks at their programmed feeds alone.
  j["build_time_s"] = sim.build_time.total_s;
  j["build_time_parts_s"] = build_time_parts(sim.build_time);
  j["feed_time_s"] = sim.feed_time_s;
  j["reorientations"] = plan.reorientations;
  j["support_free"] = plan.unsupported_area_mm2 == 0.0;
  j["unsupported_area_mm2"] = plan.unsupported_area_mm2;
  j["max_tilt_deg"] = plan.max_tilt_deg;
  j["thin_regions"] = plan.thin_regions;
  j["thin_area_mm2"] = plan.thin_area_mm2;
  j["volume_estimate_mm3"] = plan.layers.volume_estimate_mm3;
  j["fidelity"] = {{"max_cusp_mm", plan.fidelity.max_cusp_mm},
                   {"volume_difference_mm3", plan.fidelity.volume_difference_mm3},
                   {"volume_difference_share", plan.fidelity.volume_difference_share}};
  j["moves"] = sim.moves;
  j["limit_violations"] = sim.limit_violations;
  j["max_tip_deviation_mm"] = sim.max_tip_deviation_mm;
  j["max_axis_deviation_deg"] = sim.max_axis_deviation_deg;
  j["axes_turned"] = plan.axes_turned;
  j["tilts_eased"] = plan.tilts_eased;
  j["travel_detours"] = plan.travel_detours;
  j["relief_rounds"] = plan.relief_rounds;
  if (check != nullptr) {
    // The program read back through forward kinematics against the build model (docs/plan.md).
    j["build_check"] = {{"samples", check->samples},
                        {"head_collisions", check->head_collisions},
                        {"worst_head_depth_mm", check->worst_head_depth_mm},
                        {"worst_head_line", check->worst_head_line},
                        {"head_collisions_depositing", check->head_collisions_depositing},
                        {"deposit_samples", check->deposit_samples},
                        {"ungrounded_samples", check->ungrounded_samples},
                        {"ground_mm", check->ground_mm},
                        {"ground_lateral_mm", check->ground_lateral_mm},
                        {"mid_air_regions", check->mid_air_regions},
                        {"process_on_s", check->process_on_s},
                        {"stalled_s", check->stalled_s},
                        {"process_on_dwell_s", check->process_on_dwell_s},
                        {"material_checks", check->material_checks},
                        {"material_collisions", check->material_collisions},
                        {"prebuilt_collisions", check->prebuilt_collisions},
                        {"worst_material_depth_mm", check->worst_material_depth_mm},
                        {"problems", check->first_problems}};
    j["collisions"] = check->collisions;
    nlohmann::json list = nlohmann::json::array();
    for (const verify::Collision& c : check->collision_list) {
      list.push_back({{"line", c.line}, {"layer", c.layer}, {"region", c.region}, {"point", {c.tip.x, c.tip.y, c.tip.z}},
                      {"body", c.body}, {"depth_mm", c.depth_mm}});
    }
    j["collision_list"] = std::move(list);
  }
  if (const post::GcodeStats* r = meta.robot) {
    // The robot's own inverse kinematics over every written target (post/rapid.h).
    j["robot"] = {{"targets", r->robot_targets},
                  {"configuration_changes", r->robot_config_changes},
                  {"near_wrist_singularity", r->robot_near_singular},
                  {"min_wrist_deg", r->robot_min_wrist_deg},
                  {"min_joint_margin_deg", r->robot_min_joint_margin_deg},
                  {"max_joint_step_deg", r->robot_max_joint_step_deg}};
  }
  j["substrate"] = {{"x_mm", {plan.build_model.substrate.x_min_mm, plan.build_model.substrate.x_max_mm}},
                    {"y_mm", {plan.build_model.substrate.y_min_mm, plan.build_model.substrate.y_max_mm}},
                    {"top_z_mm", plan.build_model.substrate.top_z_mm},
                    {"thickness_mm", plan.build_model.substrate.thickness_mm}};
  j["axis_ranges"] = {{"x", {sim.x_mm.min, sim.x_mm.max}},
                      {"y", {sim.y_mm.min, sim.y_mm.max}},
                      {"z", {sim.z_mm.min, sim.z_mm.max}},
                      {"tilt", {sim.a_or_b_deg.empty() ? 0.0 : sim.a_or_b_deg.min, sim.a_or_b_deg.empty() ? 0.0 : sim.a_or_b_deg.max}},
                      {"c", {sim.c_deg.empty() ? 0.0 : sim.c_deg.min, sim.c_deg.empty() ? 0.0 : sim.c_deg.max}}};
  return j.dump(2) + "\n";
}

std::string timings_json(const planner::Plan& plan, const PlanMeta& meta) {
  nlohmann::ordered_json j;
  if (!meta.set_id.empty()) j["set_id"] = meta.set_id;
  // choose: every candidate plan tried, the chosen one's slice … fidelity included.
  j["timings_s"] = {{"read", meta.read_s},           {"repair", meta.repair_s},         {"choose", meta.choose_s},
                    {"slice", plan.times.slice_s},   {"toolpath", plan.times.toolpath_s}, {"sequence", plan.times.sequence_s},
                    {"support", plan.times.support_s}, {"fidelity", plan.times.fidelity_s}, {"program", plan.times.program_s},
                    {"gcode", meta.gcode_s},           {"simulate", meta.simulate_s},     {"verify", meta.verify_s}};
  return j.dump(2) + "\n";
}

std::string simulation_json(const verify::SimulationReport& r) {
  nlohmann::ordered_json j;
  j["moves"] = r.moves;
  j["rapid_moves"] = r.rapid_moves;
  j["path_length_mm"] = r.path_length_mm;
  j["deposit_length_mm"] = r.deposit_length_mm;
  j["feed_time_s"] = r.feed_time_s;
  j["build_time_s"] = r.build_time.total_s;
  j["build_time_parts_s"] = build_time_parts(r.build_time);
  auto span = [](const verify::AxisSpan& s) { return s.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json::array({s.min, s.max}); };
  j["axis_ranges"] = {{"x", span(r.x_mm)}, {"y", span(r.y_mm)}, {"z", span(r.z_mm)}, {"tilt", span(r.a_or_b_deg)}, {"c", span(r.c_deg)}};
  j["limit_violations"] = r.limit_violations;
  j["violations"] = r.violations;
  j["program_end"] = r.program_end;
  j["compared_with_plan"] = r.compared_with_plan;
  j["max_tip_deviation_mm"] = r.max_tip_deviation_mm;
  j["max_axis_deviation_deg"] = r.max_axis_deviation_deg;
  return j.dump(2);
}

}  // namespace polyaxis::report
