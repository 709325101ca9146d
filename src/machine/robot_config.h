// Reading the machine file's "robot" and "positioner" blocks (machine.h RobotCell).
#pragma once

#include <nlohmann/json.hpp>

#include "core/config_json.h"
#include "polyaxis/machine/machine.h"

namespace polyaxis::machine::detail {

// Fills M.robot from ROOT's "robot" and "positioner" when either is there; records the first
// problem in R (kUsage naming the dotted key). Both blocks go with "post": "abb-rapid" on a
// table-table kinematics (the positioner's); M.post and M.kind must be read first.
void read_robot_cell(core::detail::ConfigReader& r, const nlohmann::json& root, MachineConfig& m);

}  // namespace polyaxis::machine::detail
