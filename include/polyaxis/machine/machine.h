// The machine file: kinematics, axis limits, pivot offsets, feed limits and the nozzle (SPEC §2.7).
// Parameters of the table-table kinematics mirror LinuxCNC's xyzac-trt-kins / xyzbc-trt-kins HAL pins
// (x/y/z-rot-point, x/y/z-offset, tool-offset, see kinematics.h), so a LinuxCNC configuration can be
// copied over number for number. Degrees appear here because this is an edge (config); the
// kinematics convert once.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "polyaxis/core/result.h"
#include "polyaxis/core/vec3.h"

namespace polyaxis::machine {

enum class Kinematics {
  k3Axis,               // "xyz": tool along machine +Z, no rotary axes
  kTableTiltA_RotaryC,  // "xyzac-trt": table tilts about X (A), rotary table C mounted on it
  kTableTiltB_RotaryC,  // "xyzbc-trt": table tilts about Y (B), rotary table C mounted on it
  kHeadTiltA_RotaryC,   // "xyzac-head": the head turns about Z (C) and tilts about its X (A); the table is fixed
  kHeadTiltB_RotaryC,   // "xyzbc-head": the head turns about Z (C) and tilts about its Y (B), LinuxCNC's 5axiskins
};

// "xyz", "xyzac-trt", "xyzbc-trt", "xyzac-head", "xyzbc-head": the names machine files use.
std::string_view kinematics_name(Kinematics kind);
// 'A' or 'B' for the 5-axis machines, '\0' for 3-axis.
char tilt_axis_letter(Kinematics kind);
inline bool has_rotary_axes(Kinematics kind) { return kind != Kinematics::k3Axis; }
// The head tilts and turns; the part stays fixed on the table, so gravity does not turn with a
// region's build direction (the planner keeps build directions within the process's
// off_vertical_max_deg of +Z there).
inline bool tilts_head(Kinematics kind) { return kind == Kinematics::kHeadTiltA_RotaryC || kind == Kinematics::kHeadTiltB_RotaryC; }
// The table tilts and turns the part under a vertical tool.
inline bool turns_table(Kinematics kind) { return kind == Kinematics::kTableTiltA_RotaryC || kind == Kinematics::kTableTiltB_RotaryC; }

// The program's dialect ("post" in the machine file): the writer behind post::write_program and
// the reader of simulate and verify.
enum class PostDialect {
  kLinuxCnc,       // "linuxcnc": ISO G-code, joint values for identity kinematics (post/gcode.h)
  kSiemensTraori,  // "siemens-traori": Sinumerik TRAORI, the tip and the tool vector A3 B3 C3 in the
                   // workpiece frame, the controller's kinematics (post/traori.h)
  kAbbRapid,       // "abb-rapid": an ABB RAPID module for a robot over a positioner, robtargets in a
                   // work object on the positioner (post/rapid.h); needs "robot" and "positioner"
  kIsoTcp,         // "iso-tcp": ISO G-code under tool centre point control (G43.4): the tip in the
                   // workpiece frame and the rotary axes' words, the controller's kinematics (post/iso_tcp.h)
  k3mfToolpath,    // "3mf-toolpath": a 3MF package with the Toolpath Extension's 6-axis poses (the tip
                   // and the tool's frame, part frame) beside the part (post/toolpath_3mf.h)
};
std::string_view post_dialect_name(PostDialect dialect);
// The file extension of the dialect's program: ".ngc", ".mpf", ".mod", ".nc", ".build.3mf" (the
// double extension the Toolpath Extension recommends for build-ready packages).
inline std::string_view program_extension(PostDialect dialect) {
  switch (dialect) {
    case PostDialect::kSiemensTraori: return ".mpf";
    case PostDialect::kAbbRapid: return ".mod";
    case PostDialect::k3mfToolpath: return ".build.3mf";
    case PostDialect::kIsoTcp: return ".nc";
    case PostDialect::kLinuxCnc: break;
  }
  return ".ngc";
}
// Whether the dialect's program is text read line by line (G-code, RAPID), not a package.
inline bool program_is_text(PostDialect dialect) { return dialect != PostDialect::k3mfToolpath; }

struct AxisRange {
  double min = 0.0;  // mm for X Y Z, degrees for A B C
  double max = 0.0;
};

// Table-table pivot, exactly LinuxCNC's trt-kins pins (all mm):
struct TrtPivot {
  double x_rot_point_mm = 0.0;  // centre of rotation of C relative to machine zero
  double y_rot_point_mm = 0.0;
  double z_rot_point_mm = 0.0;
  double x_offset_mm = 0.0;     // xyzbc only: B axis relative to the C axis, along X
  double y_offset_mm = 0.0;     // xyzac only: A axis relative to the C axis, along Y
  double z_offset_mm = 0.0;     // tilt axis relative to the C axis, along Z
  double tool_offset_mm = 0.0;  // motion.tooloffset.z, added to z_offset as trt-kins does
  // false: LinuxCNC 2.9's trt-kins rotation sense (opposite to the conventional directions);
  // true: conventional right-hand directions (the later conventional-directions pin).
  bool conventional_directions = false;
  // Head-head machines only: from the nozzle tip up the tool axis to the point where the tilt and
  // C axes meet (LinuxCNC 5axiskins' pivot-length), mm, > 0. See kinematics.h.
  double pivot_length_mm = 0.0;
};

struct FeedLimits {
  double linear_max_mm_min = 6000.0;  // largest XYZ path feed the machine accepts
  double rotary_max_deg_min = 3600.0;  // largest angular feed of any rotary axis
};

// How fast the axes may change speed, and how far the controller may round a corner to keep
// moving ("accel" in the machine file, optional: these defaults). LinuxCNC's trajectory planner
// limits each axis to its acceleration and blends consecutive moves within G64 P (the program
// header carries blend_tolerance_mm as G64 P); the build-time estimate (verify/simulate.h) times
// moves the same way.
struct AccelLimits {
  double linear_mm_s2 = 1000.0;      // each of X, Y, Z
  double rotary_deg_s2 = 3600.0;     // each rotary axis
  double blend_tolerance_mm = 0.05;  // G64 P: the largest deviation from a corner the blend may take
};

// Dwivedi Eq. 2: r(z) = z·tan(θ) for z ≤ z1, R above (up to z1 + the cylinder's height).
struct NozzleModel {
  double tip_half_angle_deg = 30.0;  // θ, cone half-angle at the tip
  double cone_height_mm = 20.0;      // z1
  double cylinder_radius_mm = 25.0;  // R
  double cylinder_height_mm = 150.0; // length of the cylinder above the cone
};

// A box fixed to the head (a powder feeder, a camera, the wire feeder), in the tool frame: origin
// at the nozzle tip, +Z up the nozzle, X and Y the machine's X and Y. mm.
struct HeadBox {
  double min_mm[3] = {0, 0, 0};
  double max_mm[3] = {0, 0, 0};
};

// The machine table: a disc whose top is the plane the substrate plate is clamped to. On a
// table-table machine it turns with the part, so in the part frame it is fixed.
struct TableModel {
  double radius_mm = 250.0;
};

// A frame standing on the cell's floor: its origin in the world and its turn about world Z.
struct FloorFrame {
  double origin_mm[3] = {0, 0, 0};
  double rz_deg = 0.0;
};

// A 6-axis robot carrying the torch over a positioner (machine/robot.h has the model and frames):
// "robot" and "positioner" in the machine file, with "post": "abb-rapid". The positioner's axes
// are the machine's table kinematics (xyzac-trt or xyzbc-trt).
struct RobotCell {
  std::string model;  // for the program's header, e.g. "ABB IRB 2400"
  // Ortho-parallel arm with spherical wrist (robot.h), mm: shoulder offset a1, elbow offset a2,
  // lateral offset b, base height c1, lower arm c2, upper arm c3, wrist to flange c4.
  double a1_mm = 0, a2_mm = 0, b_mm = 0, c1_mm = 0, c2_mm = 0, c3_mm = 0, c4_mm = 0;
  std::array<double, 6> sign{1, 1, 1, 1, 1, 1};  // θi = signi·qi + zeroi
  std::array<double, 6> zero_deg{};
  std::array<double, 6> min_deg{}, max_deg{};     // the controller's joint limits
  FloorFrame base;                                // the robot's base frame in the world
  double tcp_mm[3] = {0, 0, 0};                   // the torch's TCP on the flange (tooldata tframe)
  double tcp_quaternion[4] = {1, 0, 0, 0};        //   its orientation, w x y z, z toward the work
  double tool_mass_kg = 5.0;                      //   the torch's mass (tooldata tload), its centre half way out
  double wrist_margin_deg = 5.0;                  // |θ5| below this counts as near the wrist singularity
  FloorFrame positioner;                          // the positioner's fixed frame in the world
  std::string positioner_unit = "STN1";           // its mechanical unit (the work object's ufmec)
};

struct MachineConfig {
  std::string name;
  Kinematics kind = Kinematics::k3Axis;
  AxisRange x_mm, y_mm, z_mm;
  AxisRange tilt_deg;          // A (xyzac-trt) or B (xyzbc-trt); unused on 3-axis
  AxisRange c_deg;             // unused when c_continuous or on 3-axis
  bool c_continuous = false;   // C turns without end stops
  // limits.c.unwind: a continuous C is brought back near 0 by whole turns at the program's unwind
  // points (post::ProgramPoint::c_unwind). A limited C is always unwound there, toward the middle
  // of its range. See unwinds_c().
  bool c_unwind = false;
  TrtPivot pivot;
  FeedLimits feed;
  AccelLimits accel;  // "accel", optional
  NozzleModel nozzle;
  std::vector<HeadBox> head_boxes;  // optional, "head_boxes" in the file
  TableModel table;
  PostDialect post = PostDialect::kLinuxCnc;  // "post", optional
  std::optional<RobotCell> robot;             // exactly with post abb-rapid
};

// True when the program should unwind C: a 5-axis machine whose C has end stops, or whose
// continuous C asks for it (limits.c.unwind).
bool unwinds_c(const MachineConfig& machine);

// Where a part's footprint is centred and the table is, in program coordinates (x, y; z = 0): on a
// table-table machine the rotary table's axis, X = Y = 0 of the part frame; on a 3-axis or
// head-head machine, whose limits need not contain 0 (a gantry's run from 0 to 1200), the middle of
// the X and Y travel.
core::Vec3 work_centre_mm(const MachineConfig& machine);

// The C (degrees) that an unwind turns to from C_DEG, when C will then sweep over
// [C + SWEEP_MIN_DEG, C + SWEEP_MAX_DEG] until the next unwind: C_DEG plus whole turns, chosen so
// that the sweep fits inside a limited range with its middle nearest the range's middle (nearest
// the middle when it fits nowhere), or is centred nearest 0 on a continuous C.
double unwound_c_deg(const MachineConfig& machine, double c_deg, double sweep_min_deg, double sweep_max_deg);

// Parses a machine file (JSON; // and /* */ comments allowed). Every problem is ErrorCode::kUsage
// with SOURCE and the dotted key in the message: unknown or duplicate keys (P6), non-finite or
// absurd (|v| > 1e9) numbers, including 1e999 which parses as inf (P5), min > max naming both keys
// (P3), unknown kinematics listing the supported ones or a missing axis (P4). Cost: linear in size.
core::Result<MachineConfig> parse_machine(std::string_view json, const std::string& source);

// The embedded default machine file: a 5-axis table-table A/C deposition machine (same text as
// examples/machines/ded5_ac.json).
std::string_view default_machine_json();

}  // namespace polyaxis::machine
