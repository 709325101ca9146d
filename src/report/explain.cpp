#include "polyaxis/report/explain.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>

#include "polyaxis/verify/verify.h"

namespace polyaxis::report {
namespace {

using Json = nlohmann::ordered_json;

std::string name_of(const PlanView& view, std::uint32_t layer) {
  const ViewLayer& l = view.layers.at(layer);
  return fmt::format("R{}L{}", l.region, l.order.region_layer);
}

const planner::Rule* rule_of(const PlanView& view, std::string_view id) {
  for (const planner::Rule& r : view.rules) {
    if (r.id == id) return &r;
  }
  return nullptr;
}

std::string says(const PlanView& view, std::string_view id) {
  const planner::Rule* r = rule_of(view, id);
  return r ? r->says : std::string("(not in this plan's rule base)");
}

Json rule_json(const PlanView& view, std::string_view id) {
  Json j{{"id", std::string(id)}, {"says", says(view, id)}};
  Json params = Json::object();
  if (const planner::Rule* r = rule_of(view, id)) {
    for (const auto& [key, value] : r->parameters) params[key] = value;
  }
  j["parameters"] = std::move(params);
  return j;
}

std::string params_text(const Json& rule) {
  std::string out;
  for (const auto& [key, value] : rule.at("parameters").items()) out += fmt::format("{}{} = {:.6g}", out.empty() ? " [" : ", ", key, value.get<double>());
  return out.empty() ? out : out + "]";
}

Json vec_json(Vec3 v) { return Json::array({v.x, v.y, v.z}); }

double angle_deg(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(core::dot(core::normalized(a), core::normalized(b)), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

std::optional<std::uint32_t> parse_u32(std::string_view s) {
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

}  // namespace

core::Result<std::uint32_t> find_layer(const PlanView& view, std::string_view name) {
  auto bad = [&](std::string why) {
    return core::make_error(core::ErrorCode::kUsage, fmt::format("--layer {}: {}", name, why));
  };
  if (!name.empty() && name.front() == '#') name.remove_prefix(1);
  if (auto k = parse_u32(name)) {
    if (*k >= view.layers.size()) return bad(fmt::format("the plan has {} layers (build positions 0 to {})", view.layers.size(), view.layers.size() - 1));
    return *k;
  }
  const std::size_t l = name.find_first_of("Ll");
  if (name.size() < 4 || (name.front() != 'R' && name.front() != 'r') || l == std::string_view::npos) {
    return bad("expected R<region>L<n> (region's n-th layer, from 1) or a build position");
  }
  const auto region = parse_u32(name.substr(1, l - 1)), n = parse_u32(name.substr(l + 1));
  if (!region || !n) return bad("expected R<region>L<n> (region's n-th layer, from 1) or a build position");
  std::uint32_t count = 0;
  for (std::size_t k = 0; k < view.layers.size(); ++k) {
    if (view.layers[k].region != *region) continue;
    ++count;
    if (view.layers[k].order.region_layer == *n) return static_cast<std::uint32_t>(k);
  }
  if (count == 0) return bad(fmt::format("the plan has no region {}", *region));
  return bad(fmt::format("region {} has {} layers (L1 to L{})", *region, count, count));
}

Explanation explain_layer(const PlanView& view, std::uint32_t k) {
  const ViewLayer& l = view.layers.at(k);
  Json j;
  j["layer"] = name_of(view, k);
  j["build_position"] = k;
  j["layers"] = view.layers.size();
  j["region"] = l.region;
  j["region_layer"] = l.order.region_layer;
  j["rule"] = rule_json(view, l.order.rule);
  j["level"] = l.order.level;
  j["after"] = k > 0 ? Json(name_of(view, k - 1)) : Json(nullptr);
  j["before"] = k + 1 < view.layers.size() ? Json(name_of(view, k + 1)) : Json(nullptr);
  Json with = Json::array();
  for (const std::uint32_t i : l.order.interferes_with) with.push_back({{"layer", name_of(view, i)}, {"build_position", i}, {"level", view.layers[i].order.level}});
  j["interferes_with"] = std::move(with);
  j["interferences"] = l.order.interferences;
  j["direction"] = vec_json(l.normal);
  j["tilt"] = rule_json(view, l.tilt_rule);
  j["max_tilt_deg"] = l.max_tilt_deg;
  j["tilted_points"] = l.tilted_points;
  j["turned_points"] = l.turned_points;
  j["eased_points"] = l.eased_points;
  j["tilt_range_deg"] = {l.tilt_deg[0], l.tilt_deg[1]};
  j["c_range_deg"] = {l.c_deg[0], l.c_deg[1]};
  std::uint32_t turns = 0;
  for (const planner::Reorientation& r : view.reorientations) turns += r.layer == k ? 1 : 0;
  j["reorientations"] = turns;

  std::string t = fmt::format("layer {} (region {}'s layer {}) is number {} of {} in the build order\n", j["layer"].get<std::string>(), l.region,
                              l.order.region_layer, k, view.layers.size());
  t += fmt::format("  placed by {}: {}{}\n", l.order.rule, says(view, l.order.rule), params_text(j["rule"]));
  t += fmt::format("  after {}, before {}\n", k > 0 ? name_of(view, k - 1) : std::string("nothing (it starts the build)"),
                   k + 1 < view.layers.size() ? name_of(view, k + 1) : std::string("nothing (it ends the build)"));
  if (l.order.interferences == 0) {
    t += "  interference level 0: its C-space contour overlaps no layer of another region\n";
  } else {
    std::string names;
    for (const std::uint32_t i : l.order.interferes_with) names += (names.empty() ? "" : ", ") + name_of(view, i);
    t += fmt::format("  interference level {}: its C-space contour overlaps {} layers of other regions: {}{}\n", l.order.level,
                     l.order.interferences, names, l.order.interferences > l.order.interferes_with.size() ? ", …" : "");
  }
  t += fmt::format("  direction ({:.3f}, {:.3f}, {:.3f}); torch by {}: {}{}\n", l.normal.x, l.normal.y, l.normal.z, l.tilt_rule,
                   says(view, l.tilt_rule), params_text(j["tilt"]));
  t += fmt::format("  max tilt {:.1f} deg; {} deposit points tilted, {} turned for clearance or reach, {} eased to clear the deposit; {} "
                   "reorientations\n",
                   l.max_tilt_deg, l.tilted_points, l.turned_points, l.eased_points, turns);
  if (!view.tilt_axis.empty()) {
    t += fmt::format("  machine: {} {:.2f} to {:.2f} deg, C {:.2f} to {:.2f} deg\n", view.tilt_axis, l.tilt_deg[0], l.tilt_deg[1], l.c_deg[0],
                     l.c_deg[1]);
  }
  return {t, j.dump(2) + "\n"};
}

core::Result<Explanation> explain_region(const PlanView& view, std::uint32_t id) {
  const planner::PlanRegion* r = nullptr;
  for (const planner::PlanRegion& x : view.regions) r = x.id == id ? &x : r;
  if (r == nullptr) {
    std::string ids;
    for (const planner::PlanRegion& x : view.regions) ids += fmt::format("{}{}", ids.empty() ? "" : ", ", x.id);
    return core::make_error(core::ErrorCode::kUsage, fmt::format("--region {}: the plan's regions are {}", id, ids));
  }
  std::optional<std::uint32_t> first, last;
  std::uint32_t count = 0;
  for (std::uint32_t k = 0; k < view.layers.size(); ++k) {
    if (view.layers[k].region != id) continue;
    if (!first) first = k;
    last = k, ++count;
  }
  const Vec3 d = core::normalized(r->direction);
  Json j;
  j["region"] = id;
  j["rule"] = rule_json(view, r->rule);
  j["parent"] = r->parent ? Json(*r->parent) : Json(nullptr);
  j["rests_on"] = r->rests_on;
  j["direction"] = vec_json(d);
  j["base_point"] = vec_json(r->base_point);
  j["volume_mm3"] = r->volume_mm3;
  j["overhang_mm2"] = r->overhang_mm2;
  j["support_free"] = r->support_free;
  j["layers"] = count;
  j["layer_strategy"] = {{"strategy", slicing::layer_strategy_name(r->layers)}, {"rule", rule_json(view, r->layers_rule)}, {"why", r->layers_why}};
  j["build_positions"] = first ? Json::array({*first, *last}) : Json(nullptr);
  j["prebuilt"] = r->prebuilt;
  std::string t = fmt::format("region {}{}\n", id, r->parent ? fmt::format(", child of region {}", *r->parent) : std::string(", the root"));
  t += fmt::format("  exists by \"{}\": {}{}\n", r->rule, says(view, r->rule), params_text(j["rule"]));
  if (!r->rests_on.empty()) {
    std::string on;
    for (const std::uint32_t x : r->rests_on) on += fmt::format("{}{}", on.empty() ? "" : ", ", x);
    t += fmt::format("  rests on region {}: built after it\n", on);
  }
  t += fmt::format("  built along ({:.3f}, {:.3f}, {:.3f}), {:.1f} deg from the table's normal, from its base at ({:.2f}, {:.2f}, {:.2f}): the "
                   "inward normal of its base\n",
                   d.x, d.y, d.z, angle_deg(d, {0, 0, 1}), r->base_point.x, r->base_point.y, r->base_point.z);
  if (!r->direction_rule.empty()) {
    j["direction_rule"] = {{"rule", rule_json(view, r->direction_rule)}, {"why", r->direction_why}};
    t += fmt::format("  direction by \"{}\": {}{}; here: {}\n", r->direction_rule, says(view, r->direction_rule),
                     params_text(j["direction_rule"]["rule"]), r->direction_why);
  }
  t += fmt::format("  {:.1f} mm3; {:.1f} mm2 overhang along its direction as decomposed; {}\n", r->volume_mm3, r->overhang_mm2,
                   r->support_free ? "support-free as planned" : "not support-free as planned");
  if (first) t += fmt::format("  {} layers, at build positions {} to {}\n", count, *first, *last);
  if (r->prebuilt) {
    t += "  prebuilt: on the table before the program starts, not deposited; the head is checked against it\n";
    return Explanation{t, j.dump(2) + "\n"};
  }
  t += fmt::format("  {} layers by \"{}\": {}{}{}\n", slicing::layer_strategy_name(r->layers), r->layers_rule, says(view, r->layers_rule),
                   params_text(j["layer_strategy"]["rule"]), r->layers_why.empty() ? "" : "; here: " + r->layers_why);
  return Explanation{t, j.dump(2) + "\n"};
}

core::Result<Explanation> explain_point(const PlanView& view, std::uint64_t point) {
  if (point >= view.program.size()) {
    return core::make_error(core::ErrorCode::kUsage,
                            fmt::format("--point {}: the program has {} points (0 to {})", point, view.program.size(), view.program.size() - 1));
  }
  const post::ProgramPoint& p = view.program[point];
  const ViewLayer& l = view.layers.at(p.layer);
  const double tilt = angle_deg(p.tool_axis_part, l.normal);
  const verify::PointClearance c = verify::clearance_at(view.build_model, view.program, point, view.bead_width_mm);
  Json j;
  j["point"] = point;
  j["layer"] = name_of(view, p.layer);
  j["build_position"] = p.layer;
  j["region"] = p.region;
  j["tip_mm"] = vec_json(p.tip_part_mm);
  j["tool_axis"] = vec_json(core::normalized(p.tool_axis_part));
  j["process_on"] = p.process_on;
  j["feed_mm_s"] = p.feed_mm_s;
  j["tilt_from_layer_deg"] = tilt;
  j["tilt"] = rule_json(view, l.tilt_rule);
  j["clearance_fixture_mm"] = c.fixture_mm;
  j["clearance_deposit_mm"] = c.deposit_mm ? Json(*c.deposit_mm) : Json(nullptr);
  const std::string body = c.deposit_mm && c.deposit_layer < view.layers.size()
                               ? fmt::format("deposit of layer {} (build position {})", name_of(view, c.deposit_layer), c.deposit_layer)
                               : c.deposit_body;
  j["nearest_deposit"] = c.deposit_mm ? Json{{"body", body}, {"layer", c.deposit_layer}, {"point", vec_json(c.deposit_point)}} : Json(nullptr);
  const Vec3 a = core::normalized(p.tool_axis_part);
  std::string t = fmt::format("point {} of {}: layer {} (region {}), process {}, feed {:.1f} mm/s\n", point, view.program.size(),
                              j["layer"].get<std::string>(), p.region, p.process_on ? "on" : "off", p.feed_mm_s);
  t += fmt::format("  tip ({:.3f}, {:.3f}, {:.3f}) mm, tool axis ({:.4f}, {:.4f}, {:.4f}), table frame\n", p.tip_part_mm.x, p.tip_part_mm.y,
                   p.tip_part_mm.z, a.x, a.y, a.z);
  t += fmt::format("  {:.2f} deg from the layer's normal; the layer's torch by {}: {}{}\n", tilt, l.tilt_rule, says(view, l.tilt_rule),
                   params_text(j["tilt"]));
  t += fmt::format("  clearance to the plate or table: {:.3f} mm{}\n", c.fixture_mm, c.fixture_mm < 0.0 ? " (inside: a collision)" : "");
  if (c.deposit_mm) {
    t += fmt::format("  clearance to the deposit before it: {:.3f} mm, nearest the {} at ({:.3f}, {:.3f}, {:.3f}){}\n", *c.deposit_mm,
                     body, c.deposit_point.x, c.deposit_point.y, c.deposit_point.z, *c.deposit_mm < 0.0 ? " (inside: a collision)" : "");
  } else {
    t += fmt::format("  no deposit before it beyond {:.1f} bead widths of the tip\n", verify::kIgnoreBeads);
  }
  return Explanation{t, j.dump(2) + "\n"};
}

}  // namespace polyaxis::report
