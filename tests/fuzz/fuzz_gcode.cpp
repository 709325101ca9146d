// libFuzzer target: the G-code reader (`polyaxis simulate GCODE`, `polyaxis view --gcode`) on
// arbitrary bytes, in each dialect the posts write: the first byte picks the machine (LinuxCNC
// joint values on a table-table, a head-head or a 3-axis machine, Sinumerik TRAORI tool vectors,
// or an ABB RAPID module on the robot cell of examples/machines/robot_abb_positioner.json). A program is read or refused with kInvalidInput naming the line, or kMachineLimit for
// a tool vector no axis pose reaches; never a signal. The playback frames of a program read have
// finite poses and a clock that never runs backwards.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "program_reader_checks.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "polyaxis/verify/playback.h"
#include "polyaxis/verify/simulate.h"


namespace {

// examples/machines/robot_abb_positioner.json without its comments.
constexpr std::string_view kRobotCell = R"({
  "name": "robot_abb_positioner", "kinematics": "xyzac-trt",
  "limits": {"x": {"min": -400, "max": 400}, "y": {"min": -400, "max": 400}, "z": {"min": -200, "max": 600},
             "a": {"min": -120, "max": 120}, "c": {"continuous": true, "unwind": false}},
  "pivot": {"z_offset_mm": -80, "conventional_directions": true},
  "feed": {"linear_max_mm_min": 6000, "rotary_max_deg_min": 3600},
  "nozzle": {"tip_half_angle_deg": 15, "cone_height_mm": 40, "cylinder_radius_mm": 12, "cylinder_height_mm": 150},
  "post": "abb-rapid",
  "robot": {"model": "ABB IRB 2400", "geometry_mm": {"a1": 100, "a2": -135, "b": 0, "c1": 615, "c2": 705, "c3": 755, "c4": 85},
            "joints": {"zero_deg": [0, 0, 90, 0, 0, 0], "min_deg": [-180, -100, -60, -200, -120, -400], "max_deg": [180, 110, 65, 200, 120, 400]},
            "tcp": {"origin_mm": [0, 0, 350], "quaternion": [1, 0, 0, 0], "mass_kg": 8}},
  "positioner": {"origin_mm": [1000, 0, 500], "unit": "STN1"}
})";

polyaxis::machine::MachineConfig machine_for(std::uint8_t pick) {
  using namespace polyaxis::machine;
  MachineConfig m = parse_machine(default_machine_json(), "default").value();
  switch (pick % 5) {
    case 4: m = parse_machine(kRobotCell, "robot").value(); break;
    case 1: m.post = PostDialect::kSiemensTraori; break;
    case 2:
      m.kind = Kinematics::kHeadTiltB_RotaryC;
      m.pivot = TrtPivot{};
      m.pivot.pivot_length_mm = 150.0;
      m.c_continuous = false;
      m.c_deg = {-360.0, 360.0};
      break;
    case 3: m.kind = Kinematics::k3Axis; break;
    default: break;
  }
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  if (size == 0) return 0;
  const machine::MachineConfig m = machine_for(data[0]);
  const process::ProcessConfig p = process::parse_process(process::default_process_json(), "default").value();
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  polyaxis::fuzz::check_program_reader(m, p, text);
  return 0;
}
