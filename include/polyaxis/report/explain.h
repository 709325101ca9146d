// `polyaxis explain PLAN.json` (SPEC §2.9): why a layer is where it is in the build order, why a
// region exists and has its direction, and what holds at one program point, answered from
// plan.json alone (the rule base, the layer order, the reorientations and the head it records).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/report/plan_view.h"

namespace polyaxis::report {

// An answer: readable text (lines ending in '\n') and the same facts as one JSON object.
struct Explanation {
  std::string text;
  std::string json;
};

// Layer "R2L5" (region 2's fifth layer, Dwivedi's naming) or "#97" / "97" (build position).
// kUsage for a malformed name or one the plan does not hold.
core::Result<std::uint32_t> find_layer(const PlanView& view, std::string_view name);

// The layer at build position LAYER: its place (rule, level, neighbours in the order), what it
// interferes with, its direction, tilt and rotary ranges.
Explanation explain_layer(const PlanView& view, std::uint32_t layer);
// Region ID (kUsage when absent): why it exists (its rule and the facts), why its direction, and
// where its layers fall in the order.
core::Result<Explanation> explain_region(const PlanView& view, std::uint32_t id);
// Program point POINT (kUsage when out of range): its pose, its layer's tilt rule, and the head's
// clearance to the plate or table and to the deposit before it (verify::clearance_at).
core::Result<Explanation> explain_point(const PlanView& view, std::uint64_t point);

}  // namespace polyaxis::report
