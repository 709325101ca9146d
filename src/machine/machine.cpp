#include "polyaxis/machine/machine.h"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "core/config_json.h"
#include "machine/robot_config.h"

namespace polyaxis::machine {

using nlohmann::json;

namespace {

constexpr std::string_view kSupportedKinematics = "xyz, xyzac-trt, xyzbc-trt, xyzac-head, xyzbc-head";

// Same text as examples/machines/ded5_ac.json (a test keeps them equal).
constexpr std::string_view kDefaultMachine = R"({
  "name": "ded5_ac",
  "kinematics": "xyzac-trt",
  "limits": {
    "x": {"min": -400, "max": 400},
    "y": {"min": -400, "max": 400},
    "z": {"min": -200, "max": 600},
    "a": {"min": -120, "max": 120},
    "c": {"continuous": true, "unwind": false}
  },
  "pivot": {
    "x_rot_point_mm": 0,
    "y_rot_point_mm": 0,
    "z_rot_point_mm": 0,
    "y_offset_mm": 0,
    "z_offset_mm": -80,
    "tool_offset_mm": 0,
    "conventional_directions": false
  },
  "feed": {"linear_max_mm_min": 6000, "rotary_max_deg_min": 3600},
  "accel": {"linear_mm_s2": 1000, "rotary_deg_s2": 3600, "blend_tolerance_mm": 0.05},
  "nozzle": {"tip_half_angle_deg": 30, "cone_height_mm": 20, "cylinder_radius_mm": 25, "cylinder_height_mm": 150},
  "table": {"radius_mm": 250}
}
)";

AxisRange read_range(core::detail::ConfigReader& r, const json& limits, std::string_view axis) {
  const std::string path = core::detail::join_key("limits", axis);
  const json& obj = limits.at(std::string(axis));
  AxisRange range;
  if (!r.check_object(obj, path, {"min", "max"})) return range;
  range.min = r.number(obj, path, "min", std::nullopt);
  range.max = r.number(obj, path, "max", std::nullopt);
  if (!r.failed()) r.require_le(range.min, path + ".min", range.max, path + ".max");
  return range;
}

// "head_boxes": [{"min_mm": [x, y, z], "max_mm": [x, y, z]}, ...] in the tool frame.
void read_head_boxes(core::detail::ConfigReader& r, const json& root, MachineConfig& m) {
  if (!r.has(root, "head_boxes")) return;
  const json& boxes = root.at("head_boxes");
  if (!boxes.is_array()) return r.fail("'head_boxes' must be an array of {\"min_mm\": [x,y,z], \"max_mm\": [x,y,z]}");
  for (std::size_t i = 0; i < boxes.size() && !r.failed(); ++i) {
    const std::string path = fmt::format("head_boxes[{}]", i);
    if (!r.check_object(boxes[i], path, {"min_mm", "max_mm"})) return;
    HeadBox box;
    for (const auto& [key, out] : {std::pair<const char*, double*>{"min_mm", box.min_mm}, {"max_mm", box.max_mm}}) {
      const json* v = boxes[i].contains(key) ? &boxes[i].at(key) : nullptr;
      if (v == nullptr || !v->is_array() || v->size() != 3) return r.fail(fmt::format("'{}.{}' must be an array of 3 numbers", path, key));
      for (std::size_t k = 0; k < 3; ++k) {
        if (!(*v)[k].is_number()) return r.fail(fmt::format("'{}.{}' must be an array of 3 numbers", path, key));
        out[k] = (*v)[k].get<double>();
        if (!std::isfinite(out[k]) || std::abs(out[k]) > core::detail::kMaxConfigMagnitude) {
          return r.fail(fmt::format("'{}.{}[{}]' is not a finite number of sane size", path, key, k));
        }
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (box.min_mm[k] > box.max_mm[k]) return r.fail(fmt::format("'{}.min_mm[{}]' exceeds '{}.max_mm[{}]'", path, k, path, k));
    }
    m.head_boxes.push_back(box);
  }
}

}  // namespace

std::string_view kinematics_name(Kinematics kind) {
  switch (kind) {
    case Kinematics::k3Axis: return "xyz";
    case Kinematics::kTableTiltA_RotaryC: return "xyzac-trt";
    case Kinematics::kTableTiltB_RotaryC: return "xyzbc-trt";
    case Kinematics::kHeadTiltA_RotaryC: return "xyzac-head";
    case Kinematics::kHeadTiltB_RotaryC: return "xyzbc-head";
  }
  return "?";
}

std::string_view post_dialect_name(PostDialect dialect) {
  switch (dialect) {
    case PostDialect::kLinuxCnc: return "linuxcnc";
    case PostDialect::kSiemensTraori: return "siemens-traori";
    case PostDialect::kAbbRapid: return "abb-rapid";
    case PostDialect::k3mfToolpath: return "3mf-toolpath";
    case PostDialect::kIsoTcp: return "iso-tcp";
  }
  return "?";
}

char tilt_axis_letter(Kinematics kind) {
  switch (kind) {
    case Kinematics::kTableTiltA_RotaryC:
    case Kinematics::kHeadTiltA_RotaryC: return 'A';
    case Kinematics::kTableTiltB_RotaryC:
    case Kinematics::kHeadTiltB_RotaryC: return 'B';
    case Kinematics::k3Axis: break;
  }
  return '\0';
}

std::string_view default_machine_json() { return kDefaultMachine; }

core::Vec3 work_centre_mm(const MachineConfig& machine) {
  if (turns_table(machine.kind)) return {};
  return {0.5 * (machine.x_mm.min + machine.x_mm.max), 0.5 * (machine.y_mm.min + machine.y_mm.max), 0.0};
}

bool unwinds_c(const MachineConfig& m) { return has_rotary_axes(m.kind) && (!m.c_continuous || m.c_unwind); }

double unwound_c_deg(const MachineConfig& m, double c_deg, double sweep_min_deg, double sweep_max_deg) {
  const double centre = m.c_continuous ? 0.0 : 0.5 * (m.c_deg.min + m.c_deg.max);
  const double mid = 0.5 * (sweep_min_deg + sweep_max_deg);
  const double k0 = std::round((centre - c_deg - mid) / 360.0);
  if (m.c_continuous) return c_deg + 360.0 * k0;
  for (const double dk : {0.0, -1.0, 1.0}) {
    const double c = c_deg + 360.0 * (k0 + dk);
    if (c + sweep_min_deg >= m.c_deg.min && c + sweep_max_deg <= m.c_deg.max) return c;
  }
  return c_deg + 360.0 * k0;
}

core::Result<MachineConfig> parse_machine(std::string_view text, const std::string& source) {
  auto doc = core::detail::parse_document(text, source);
  if (!doc) return doc.error();
  const json& root = doc.value();
  core::detail::ConfigReader r(source);
  MachineConfig m;
  if (!r.check_object(root, "", {"name", "kinematics", "limits", "pivot", "feed", "accel", "nozzle", "head_boxes", "table", "post", "robot", "positioner"})) return r.error();
  m.name = r.string(root, "", "name", std::nullopt);
  const std::string kin = r.string(root, "", "kinematics", std::nullopt);
  if (r.failed()) return r.error();
  if (kin == "xyz") {
    m.kind = Kinematics::k3Axis;
  } else if (kin == "xyzac-trt") {
    m.kind = Kinematics::kTableTiltA_RotaryC;
  } else if (kin == "xyzbc-trt") {
    m.kind = Kinematics::kTableTiltB_RotaryC;
  } else if (kin == "xyzac-head") {
    m.kind = Kinematics::kHeadTiltA_RotaryC;
  } else if (kin == "xyzbc-head") {
    m.kind = Kinematics::kHeadTiltB_RotaryC;
  } else {
    r.fail(fmt::format("unknown kinematics '{}' (supported: {})", kin, kSupportedKinematics));
    return r.error();
  }
  const bool five = has_rotary_axes(m.kind);
  const std::string tilt = tilt_axis_letter(m.kind) == 'B' ? "b" : "a";

  // Limits: X Y Z always; the tilt axis and C exactly when the kinematics has them (P4).
  if (!r.has(root, "limits")) {
    r.fail("missing key 'limits'");
    return r.error();
  }
  const json& limits = root.at("limits");
  if (five) {
    if (!r.check_object(limits, "limits", {"x", "y", "z", tilt, "c"})) return r.error();
  } else if (!r.check_object(limits, "limits", {"x", "y", "z"})) {
    return r.error();  // e.g. limits.a on an xyz machine: unknown key, listing x, y, z
  }
  for (const std::string axis : {"x", "y", "z"}) {
    if (!limits.contains(axis)) r.fail(fmt::format("missing axis definition 'limits.{}' for kinematics {}", axis, kin));
  }
  if (five) {
    for (const std::string& axis : {tilt, std::string("c")}) {
      if (!limits.contains(axis)) r.fail(fmt::format("missing axis definition 'limits.{}' for kinematics {}", axis, kin));
    }
  }
  if (r.failed()) return r.error();
  m.x_mm = read_range(r, limits, "x");
  m.y_mm = read_range(r, limits, "y");
  m.z_mm = read_range(r, limits, "z");
  if (five) {
    m.tilt_deg = read_range(r, limits, tilt);
    const json& c = limits.at("c");
    if (r.check_object(c, "limits.c", {"min", "max", "continuous", "unwind"})) {
      m.c_continuous = r.boolean(c, "limits.c", "continuous", false);
      m.c_unwind = r.boolean(c, "limits.c", "unwind", false);
      if (m.c_continuous && (c.contains("min") || c.contains("max"))) {
        r.fail("'limits.c.min'/'limits.c.max' are given but 'limits.c.continuous' is true; give one or the other");
      } else if (!m.c_continuous && c.contains("unwind")) {
        r.fail("'limits.c.unwind' applies to a continuous C; a C with end stops is always unwound");
      } else if (!m.c_continuous) {
        m.c_deg.min = r.number(c, "limits.c", "min", std::nullopt);
        m.c_deg.max = r.number(c, "limits.c", "max", std::nullopt);
        if (!r.failed()) r.require_le(m.c_deg.min, "limits.c.min", m.c_deg.max, "limits.c.max");
      }
    }
  }
  if (r.failed()) return r.error();

  // Pivot: optional, zero by default; only the offsets the kinematics uses may be non-zero. A
  // head-head machine has one: the pivot length, which it needs.
  if (tilts_head(m.kind)) {
    if (!r.has(root, "pivot")) {
      r.fail(fmt::format("missing key 'pivot.pivot_length_mm' for kinematics {}", kin));
      return r.error();
    }
    const json& p = root.at("pivot");
    if (!r.check_object(p, "pivot", {"pivot_length_mm"})) return r.error();
    m.pivot.pivot_length_mm = r.number(p, "pivot", "pivot_length_mm", std::nullopt);
    if (!r.failed() && !(m.pivot.pivot_length_mm > 0.0)) {
      r.fail(fmt::format("'pivot.pivot_length_mm' ({}) must be > 0: the distance from the nozzle tip to where the head's axes meet",
                         m.pivot.pivot_length_mm));
    }
    if (r.failed()) return r.error();
  } else if (r.has(root, "pivot")) {
    const json& p = root.at("pivot");
    if (!r.check_object(p, "pivot", {"x_rot_point_mm", "y_rot_point_mm", "z_rot_point_mm", "x_offset_mm", "y_offset_mm",
                                      "z_offset_mm", "tool_offset_mm", "conventional_directions"})) {
      return r.error();
    }
    m.pivot.x_rot_point_mm = r.number(p, "pivot", "x_rot_point_mm", 0.0);
    m.pivot.y_rot_point_mm = r.number(p, "pivot", "y_rot_point_mm", 0.0);
    m.pivot.z_rot_point_mm = r.number(p, "pivot", "z_rot_point_mm", 0.0);
    m.pivot.x_offset_mm = r.number(p, "pivot", "x_offset_mm", 0.0);
    m.pivot.y_offset_mm = r.number(p, "pivot", "y_offset_mm", 0.0);
    m.pivot.z_offset_mm = r.number(p, "pivot", "z_offset_mm", 0.0);
    m.pivot.tool_offset_mm = r.number(p, "pivot", "tool_offset_mm", 0.0);
    m.pivot.conventional_directions = r.boolean(p, "pivot", "conventional_directions", false);
    if (r.failed()) return r.error();
    // LinuxCNC's trt-kins ignore the offset along the tilt axis; a non-zero one is a mistake.
    if (m.kind == Kinematics::kTableTiltA_RotaryC && m.pivot.x_offset_mm != 0.0) {
      r.fail("'pivot.x_offset_mm' is not used by xyzac-trt (A is parallel to X): set it to 0 or remove it");
    } else if (m.kind == Kinematics::kTableTiltB_RotaryC && m.pivot.y_offset_mm != 0.0) {
      r.fail("'pivot.y_offset_mm' is not used by xyzbc-trt (B is parallel to Y): set it to 0 or remove it");
    } else if (m.kind == Kinematics::k3Axis &&
               (m.pivot.x_rot_point_mm != 0.0 || m.pivot.y_rot_point_mm != 0.0 || m.pivot.z_rot_point_mm != 0.0 ||
                m.pivot.x_offset_mm != 0.0 || m.pivot.y_offset_mm != 0.0 || m.pivot.z_offset_mm != 0.0 ||
                m.pivot.tool_offset_mm != 0.0)) {
      r.fail("'pivot' offsets are not used by xyz kinematics: set them to 0 or remove 'pivot'");
    }
  }

  if (!r.has(root, "feed")) r.fail("missing key 'feed'");
  if (r.failed()) return r.error();
  const json& f = root.at("feed");
  if (!r.check_object(f, "feed", {"linear_max_mm_min", "rotary_max_deg_min"})) return r.error();
  m.feed.linear_max_mm_min = r.number(f, "feed", "linear_max_mm_min", std::nullopt);
  m.feed.rotary_max_deg_min = r.number(f, "feed", "rotary_max_deg_min", five ? std::nullopt : std::optional<double>(1.0));
  // A machine slower than 1 mm/min or 1°/min, or faster than 1 km/min or 10⁶ °/min, is a typo.
  if (!r.failed() && !(m.feed.linear_max_mm_min >= 1.0 && m.feed.linear_max_mm_min <= 1e6)) {
    r.fail(fmt::format("'feed.linear_max_mm_min' ({}) must be between 1 and 1e6 mm/min", m.feed.linear_max_mm_min));
  }
  if (!r.failed() && five && !(m.feed.rotary_max_deg_min >= 1.0 && m.feed.rotary_max_deg_min <= 1e6)) {
    r.fail(fmt::format("'feed.rotary_max_deg_min' ({}) must be between 1 and 1e6 deg/min", m.feed.rotary_max_deg_min));
  }

  if (r.has(root, "accel")) {
    const json& a = root.at("accel");
    if (!r.check_object(a, "accel", {"linear_mm_s2", "rotary_deg_s2", "blend_tolerance_mm"})) return r.error();
    const AccelLimits defaults;
    m.accel.linear_mm_s2 = r.number(a, "accel", "linear_mm_s2", defaults.linear_mm_s2);
    m.accel.rotary_deg_s2 = r.number(a, "accel", "rotary_deg_s2", defaults.rotary_deg_s2);
    m.accel.blend_tolerance_mm = r.number(a, "accel", "blend_tolerance_mm", defaults.blend_tolerance_mm);
    // Slower than 1 mm/s² (or 1°/s²) or faster than 100 g is a typo; a blend past 10 mm is no corner.
    if (!r.failed() && !(m.accel.linear_mm_s2 >= 1.0 && m.accel.linear_mm_s2 <= 1e6)) {
      r.fail(fmt::format("'accel.linear_mm_s2' ({}) must be between 1 and 1e6 mm/s2", m.accel.linear_mm_s2));
    }
    if (!r.failed() && !(m.accel.rotary_deg_s2 >= 1.0 && m.accel.rotary_deg_s2 <= 1e6)) {
      r.fail(fmt::format("'accel.rotary_deg_s2' ({}) must be between 1 and 1e6 deg/s2", m.accel.rotary_deg_s2));
    }
    if (!r.failed() && !(m.accel.blend_tolerance_mm >= 0.0 && m.accel.blend_tolerance_mm <= 10.0)) {
      r.fail(fmt::format("'accel.blend_tolerance_mm' ({}) must be between 0 and 10 mm", m.accel.blend_tolerance_mm));
    }
  }

  if (r.has(root, "nozzle")) {
    const json& n = root.at("nozzle");
    if (!r.check_object(n, "nozzle", {"tip_half_angle_deg", "cone_height_mm", "cylinder_radius_mm", "cylinder_height_mm"})) {
      return r.error();
    }
    const NozzleModel defaults;
    m.nozzle.tip_half_angle_deg = r.number(n, "nozzle", "tip_half_angle_deg", defaults.tip_half_angle_deg);
    m.nozzle.cone_height_mm = r.number(n, "nozzle", "cone_height_mm", defaults.cone_height_mm);
    m.nozzle.cylinder_radius_mm = r.number(n, "nozzle", "cylinder_radius_mm", defaults.cylinder_radius_mm);
    m.nozzle.cylinder_height_mm = r.number(n, "nozzle", "cylinder_height_mm", defaults.cylinder_height_mm);
  }
  if (!r.failed() && !(m.nozzle.tip_half_angle_deg > 0.0 && m.nozzle.tip_half_angle_deg < 90.0)) {
    r.fail("'nozzle.tip_half_angle_deg' must be between 0 and 90 degrees (exclusive)");
  }
  if (!r.failed() && m.nozzle.cone_height_mm <= 0.0) r.fail("'nozzle.cone_height_mm' must be > 0");
  if (!r.failed() && m.nozzle.cylinder_radius_mm <= 0.0) r.fail("'nozzle.cylinder_radius_mm' must be > 0");
  if (!r.failed() && m.nozzle.cylinder_height_mm < 0.0) r.fail("'nozzle.cylinder_height_mm' must be >= 0");
  if (r.failed()) return r.error();
  read_head_boxes(r, root, m);
  if (r.has(root, "post")) {
    const std::string post = r.string(root, "", "post", std::nullopt);
    if (post == "siemens-traori") {
      m.post = PostDialect::kSiemensTraori;
    } else if (post == "abb-rapid") {
      m.post = PostDialect::kAbbRapid;
    } else if (post == "3mf-toolpath") {
      m.post = PostDialect::k3mfToolpath;
    } else if (post == "iso-tcp") {
      m.post = PostDialect::kIsoTcp;
    } else if (post != "linuxcnc") {
      r.fail(fmt::format("unknown 'post' '{}' (supported: linuxcnc, siemens-traori, iso-tcp, abb-rapid, 3mf-toolpath)", post));
    }
    if (!r.failed() && m.post == PostDialect::kSiemensTraori && !has_rotary_axes(m.kind)) {
      r.fail("'post' siemens-traori needs a 5-axis machine: TRAORI orients the tool");
    }
    if (!r.failed() && m.post == PostDialect::kIsoTcp && !has_rotary_axes(m.kind)) {
      r.fail("'post' iso-tcp needs a 5-axis machine: G43.4 keeps the tip while rotary axes turn");
    }
    if (r.failed()) return r.error();
  }
  detail::read_robot_cell(r, root, m);
  if (r.failed()) return r.error();
  if (r.has(root, "table")) {
    const json& t = root.at("table");
    if (!r.check_object(t, "table", {"radius_mm"})) return r.error();
    m.table.radius_mm = r.number(t, "table", "radius_mm", m.table.radius_mm);
    if (!r.failed() && !(m.table.radius_mm > 0.0)) r.fail("'table.radius_mm' must be > 0");
  }
  if (r.failed()) return r.error();
  return m;
}

}  // namespace polyaxis::machine
