#include "machine/robot_config.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <span>

namespace polyaxis::machine::detail {
namespace {

using nlohmann::json;

// KEY of OBJ (at PATH) as exactly OUT.size() finite numbers of sane size.
void read_numbers(core::detail::ConfigReader& r, const json& obj, const std::string& path, const char* key, std::span<double> out) {
  if (r.failed()) return;
  const json* v = obj.contains(key) ? &obj.at(key) : nullptr;
  if (v == nullptr) return r.fail(fmt::format("missing key '{}.{}'", path, key));
  if (!v->is_array() || v->size() != out.size()) return r.fail(fmt::format("'{}.{}' must be an array of {} numbers", path, key, out.size()));
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (!(*v)[k].is_number()) return r.fail(fmt::format("'{}.{}' must be an array of {} numbers", path, key, out.size()));
    out[k] = (*v)[k].get<double>();
    if (!std::isfinite(out[k]) || std::abs(out[k]) > core::detail::kMaxConfigMagnitude) {
      return r.fail(fmt::format("'{}.{}[{}]' is not a finite number of sane size", path, key, k));
    }
  }
}

void read_floor_frame(core::detail::ConfigReader& r, const json& obj, const std::string& path, FloorFrame& f) {
  read_numbers(r, obj, path, "origin_mm", f.origin_mm);
  if (!r.failed()) f.rz_deg = r.number(obj, path, "rz_deg", 0.0);
}

void read_geometry(core::detail::ConfigReader& r, const json& robot, RobotCell& c) {
  if (!r.has(robot, "geometry_mm")) return r.fail("missing key 'robot.geometry_mm'");
  const json& g = robot.at("geometry_mm");
  if (!r.check_object(g, "robot.geometry_mm", {"a1", "a2", "b", "c1", "c2", "c3", "c4"})) return;
  for (const auto& [key, out] : {std::pair<const char*, double*>{"a1", &c.a1_mm}, {"a2", &c.a2_mm}, {"b", &c.b_mm}, {"c1", &c.c1_mm},
                                 {"c2", &c.c2_mm}, {"c3", &c.c3_mm}, {"c4", &c.c4_mm}}) {
    *out = r.number(g, "robot.geometry_mm", key, std::nullopt);
  }
  if (r.failed()) return;
  if (!(c.c2_mm > 0.0)) return r.fail(fmt::format("'robot.geometry_mm.c2' ({}) must be > 0: the lower arm's length", c.c2_mm));
  if (!(std::hypot(c.a2_mm, c.c3_mm) > 0.0)) return r.fail("'robot.geometry_mm.a2' and 'c3' are both 0: the upper arm has no length");
  if (c.c4_mm < 0.0) r.fail(fmt::format("'robot.geometry_mm.c4' ({}) must be >= 0", c.c4_mm));
}

void read_joints(core::detail::ConfigReader& r, const json& robot, RobotCell& c) {
  if (!r.has(robot, "joints")) return r.fail("missing key 'robot.joints'");
  const json& j = robot.at("joints");
  if (!r.check_object(j, "robot.joints", {"sign", "zero_deg", "min_deg", "max_deg"})) return;
  if (j.contains("sign")) read_numbers(r, j, "robot.joints", "sign", c.sign);
  if (j.contains("zero_deg")) read_numbers(r, j, "robot.joints", "zero_deg", c.zero_deg);
  read_numbers(r, j, "robot.joints", "min_deg", c.min_deg);
  read_numbers(r, j, "robot.joints", "max_deg", c.max_deg);
  for (std::size_t i = 0; i < 6 && !r.failed(); ++i) {
    if (c.sign[i] != 1.0 && c.sign[i] != -1.0) r.fail(fmt::format("'robot.joints.sign[{}]' ({}) must be 1 or -1", i, c.sign[i]));
    if (!r.failed()) r.require_le(c.min_deg[i], fmt::format("robot.joints.min_deg[{}]", i), c.max_deg[i], fmt::format("robot.joints.max_deg[{}]", i));
  }
}

void read_robot(core::detail::ConfigReader& r, const json& robot, RobotCell& c) {
  if (!r.check_object(robot, "robot", {"model", "geometry_mm", "joints", "base", "tcp", "wrist_margin_deg"})) return;
  c.model = r.string(robot, "robot", "model", std::string("robot"));
  read_geometry(r, robot, c);
  read_joints(r, robot, c);
  if (r.failed()) return;
  if (r.has(robot, "base")) {
    const json& b = robot.at("base");
    if (!r.check_object(b, "robot.base", {"origin_mm", "rz_deg"})) return;
    read_floor_frame(r, b, "robot.base", c.base);
  }
  if (!r.has(robot, "tcp")) return r.fail("missing key 'robot.tcp': the torch's TCP on the flange");
  const json& t = robot.at("tcp");
  if (!r.check_object(t, "robot.tcp", {"origin_mm", "quaternion", "mass_kg"})) return;
  c.tool_mass_kg = r.number(t, "robot.tcp", "mass_kg", std::nullopt);
  if (!r.failed() && !(c.tool_mass_kg > 0.0 && c.tool_mass_kg <= 1000.0)) {
    return r.fail(fmt::format("'robot.tcp.mass_kg' ({}) must be in (0, 1000]: the torch's mass", c.tool_mass_kg));
  }
  read_numbers(r, t, "robot.tcp", "origin_mm", c.tcp_mm);
  if (t.contains("quaternion")) read_numbers(r, t, "robot.tcp", "quaternion", c.tcp_quaternion);
  if (r.failed()) return;
  if (!(std::hypot(c.tcp_quaternion[0], c.tcp_quaternion[1], c.tcp_quaternion[2]) + std::abs(c.tcp_quaternion[3]) > 0.0)) {
    return r.fail("'robot.tcp.quaternion' is zero: give [w, x, y, z] of the TCP's turn on the flange");
  }
  c.wrist_margin_deg = r.number(robot, "robot", "wrist_margin_deg", c.wrist_margin_deg);
  if (!r.failed() && !(c.wrist_margin_deg >= 0.0 && c.wrist_margin_deg < 90.0)) {
    r.fail(fmt::format("'robot.wrist_margin_deg' ({}) must be in [0, 90)", c.wrist_margin_deg));
  }
}

void read_positioner(core::detail::ConfigReader& r, const json& root, RobotCell& c) {
  if (!r.has(root, "positioner")) return r.fail("missing key 'positioner': where the positioner stands in the cell");
  const json& p = root.at("positioner");
  if (!r.check_object(p, "positioner", {"origin_mm", "rz_deg", "unit"})) return;
  read_floor_frame(r, p, "positioner", c.positioner);
  c.positioner_unit = r.string(p, "positioner", "unit", c.positioner_unit);
  if (r.failed()) return;
  const bool identifier = !c.positioner_unit.empty() && c.positioner_unit.size() <= 16 &&
                          std::all_of(c.positioner_unit.begin(), c.positioner_unit.end(),
                                      [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_'; });
  if (!identifier) r.fail(fmt::format("'positioner.unit' ('{}') must be a mechanical unit's name: letters, digits, _ (at most 16)", c.positioner_unit));
}

}  // namespace

void read_robot_cell(core::detail::ConfigReader& r, const json& root, MachineConfig& m) {
  const bool robot = r.has(root, "robot"), positioner = r.has(root, "positioner");
  if (m.post != PostDialect::kAbbRapid) {
    if (robot || positioner) r.fail(fmt::format("'{}' is only read with \"post\": \"abb-rapid\"", robot ? "robot" : "positioner"));
    return;
  }
  if (!turns_table(m.kind)) {
    return r.fail(fmt::format("'post' abb-rapid drives a robot over a positioner: the kinematics must be the positioner's, xyzac-trt or "
                              "xyzbc-trt (not {})",
                              kinematics_name(m.kind)));
  }
  if (!robot) return r.fail("missing key 'robot': post abb-rapid needs the robot that carries the torch");
  RobotCell c;
  read_robot(r, root.at("robot"), c);
  if (!r.failed()) read_positioner(r, root, c);
  if (!r.failed()) m.robot = std::move(c);
}

}  // namespace polyaxis::machine::detail
