// What an engineer looks at in a plan (SPEC §2.10): the regions, the centroidal axis, the layers
// with their contours and unsupported pieces, the program, and the machine's rotary angles per
// layer. plan.json is this structure written out (plan_files.h); report.html shows it
// (report_html.h). Everything is in the placed frame: the rotary table's frame, Z up.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "polyaxis/analysis/centroidal_axis.h"
#include "polyaxis/core/result.h"
#include "polyaxis/post/program.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "polyaxis/planner/plan.h"
#include "polyaxis/verify/playback.h"
#include "polyaxis/verify/verify.h"

namespace polyaxis::report {

using core::Vec3;

struct ViewLayer {
  std::uint32_t index = 0;
  std::uint32_t region = 0;
  Vec3 origin, u{1, 0, 0}, v{0, 1, 0}, normal{0, 0, 1};
  double thickness_mm = 0.0;
  std::array<double, 2> thickness_range_mm{0.0, 0.0};  // least and largest over the layer (tilted layers differ)
  double area_mm2 = 0.0;
  double unsupported_area_mm2 = 0.0;
  double max_tilt_deg = 0.0;
  std::uint32_t paths = 0;
  // Machine rotary positions over the layer's program points, degrees (0 on 3-axis machines).
  std::array<double, 2> tilt_deg{0.0, 0.0};
  std::array<double, 2> c_deg{0.0, 0.0};
  // Its place in the build order and its torch (planner::LayerOrder, LayerReport).
  planner::LayerOrder order;
  std::string tilt_rule;
  std::uint32_t tilted_points = 0, turned_points = 0, eased_points = 0;
  std::vector<std::vector<Vec3>> contours;     // closed rings (last point != first), outer and holes
  std::vector<std::vector<Vec3>> unsupported;  // the unsupported pieces' rings
  // Pieces no bead covers (toolpath::ThinRegion): where (the piece's centroid, the plan's frame),
  // how large and why.
  struct Thin {
    Vec3 where;
    double area_mm2 = 0.0;
    std::string what;
  };
  std::vector<Thin> thin;
};

struct ViewAxis {
  std::vector<Vec3> nodes;
  std::vector<std::array<std::uint32_t, 3>> links;  // from, to, is_break (0 or 1)
};

// A collision found reading the program back (verify::Collision), where and what, for the viewer.
struct ViewCollision {
  Vec3 position;     // the nozzle tip, placed frame
  std::string what;  // "layer 3 region 1, line 812: the head strikes the deposit of layer 2 region 0 (0.40 mm)"
  std::uint64_t line = 0;  // its G-code line (0: not known, in plans written before it was kept)
};

// Machine playback in report.html (issue 15, item 4): the machine that runs the program and the
// program's frames as its controller reads them (verify::playback_frames).
struct ViewPlayback {
  machine::MachineConfig machine;
  std::vector<verify::PlaybackFrame> frames;
};

struct PlanView {
  std::string part;         // the part file, as given
  std::string machine;      // machine name
  std::string kinematics;   // machine::kinematics_name
  std::string tilt_axis;    // "A", "B" or "" (3-axis)
  std::string process;      // process name
  double bead_width_mm = 0.0;
  planner::Placement placement;  // part frame -> table frame
  std::string metrics_json;  // report.json's object (report_json output)
  std::vector<planner::PlanRegion> regions;  // placed
  std::optional<ViewAxis> axis;              // placed; with --decompose
  std::vector<ViewLayer> layers;
  std::vector<post::ProgramPoint> program;
  std::vector<ViewCollision> collisions;  // the first verify::kMaxListedCollisions
  // The rule base (planner::rule_base), the reorientations with their rules, and the head, table
  // and plate the plan was checked against.
  std::vector<planner::Rule> rules;
  std::vector<planner::Reorientation> reorientations;
  machine::BuildModel build_model;
  // Set by `plan` from the G-code it wrote; absent when the view is read back from plan.json.
  std::optional<ViewPlayback> playback;
};

// The view of PLAN. AXIS (part frame, before placement) may be null. METRICS_JSON is report.json.
// The rotary ranges come from inverse kinematics along the program, as the G-code writer runs it.
// CHECK, when given, supplies the collisions.
PlanView make_plan_view(const planner::Plan& plan, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                        const analysis::CentroidalAxis* axis, std::string part, std::string metrics_json,
                        const verify::BuildCheck* check = nullptr);

// METRICS_JSON as a JSON object indented by 2, keys in their order ("{}" when it is not an object).
std::string metrics_object(std::string_view metrics_json);

// plan.json (schema in docs/plan.md). Deterministic.
std::string plan_view_json(const PlanView& view);

// Reads plan.json back. kInvalidInput naming SOURCE on anything malformed (a missing key, a
// non-finite number, an index out of range).
core::Result<PlanView> read_plan_view(std::string_view json, const std::string& source);

// The program points of a plan.json (for `polyaxis simulate --plan`). kInvalidInput on anything
// malformed.
core::Result<std::vector<post::ProgramPoint>> read_plan_program(std::string_view json, const std::string& source);

}  // namespace polyaxis::report
