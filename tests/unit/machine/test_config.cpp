// Machine and process files: the embedded defaults, the examples, and RELIABILITY P1-P6.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "polyaxis/core/config_document.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

namespace polyaxis::machine {
namespace {

using core::ErrorCode;
using process::default_process_json;
using process::parse_process;
using process::ProcessConfig;
using core::apply_override;
using core::parse_config_document;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string examples(const std::string& rel) { return slurp(std::string(POLYAXIS_EXAMPLES_DIR) + "/" + rel); }

// Replaces the first occurrence of FROM in TEXT (the test fails if it is absent).
std::string edit(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string machine_error(const std::string& text) {
  auto r = parse_machine(text, "m.json");
  EXPECT_FALSE(r.ok());
  if (r.ok()) return {};
  EXPECT_EQ(r.error().code, ErrorCode::kUsage) << r.error().message;
  return r.error().message;
}

std::string process_error(const std::string& text) {
  auto r = parse_process(text, "p.json");
  EXPECT_FALSE(r.ok());
  if (r.ok()) return {};
  EXPECT_EQ(r.error().code, ErrorCode::kUsage) << r.error().message;
  return r.error().message;
}

const std::string kAc(default_machine_json());
const std::string kProc(default_process_json());

TEST(MachineConfig, DefaultIsTheAcDepositionMachine) {
  auto m = parse_machine(default_machine_json(), "default");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m.value().kind, Kinematics::kTableTiltA_RotaryC);
  EXPECT_TRUE(m.value().c_continuous);
  EXPECT_EQ(m.value().pivot.z_offset_mm, -80.0);
  EXPECT_EQ(examples("machines/ded5_ac.json"), std::string(default_machine_json()));
}

// "accel": the default machine's 1000 mm/s², 3600 °/s² and G64 P0.05; a file without it takes
// those; a value out of range names its key.
TEST(MachineConfig, AccelerationsAndBlendTolerance) {
  auto m = parse_machine(default_machine_json(), "default");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m.value().accel.linear_mm_s2, 1000.0);
  EXPECT_EQ(m.value().accel.rotary_deg_s2, 3600.0);
  EXPECT_EQ(m.value().accel.blend_tolerance_mm, 0.05);
  auto doc = parse_config_document(kAc, "ac");
  ASSERT_TRUE(doc.ok());
  nlohmann::json without = doc.value();
  without.erase("accel");
  auto defaults = parse_machine(without.dump(), "no accel");
  ASSERT_TRUE(defaults.ok()) << defaults.error().message;
  EXPECT_EQ(defaults.value().accel.linear_mm_s2, AccelLimits{}.linear_mm_s2);
  for (const auto& [key, value] : {std::pair{"linear_mm_s2", 0.5}, std::pair{"rotary_deg_s2", 2e6}, std::pair{"blend_tolerance_mm", -0.1}}) {
    nlohmann::json bad = doc.value();
    bad["accel"][key] = value;
    EXPECT_NE(machine_error(bad.dump()).find(std::string("accel.") + key), std::string::npos) << key;
  }
  nlohmann::json unknown = doc.value();
  unknown["accel"]["jerk"] = 1.0;
  EXPECT_NE(machine_error(unknown.dump()).find("jerk"), std::string::npos);
}

TEST(MachineConfig, EveryExampleParses) {
  for (const char* name : {"ded5_ac", "ded5_bc", "gantry3"}) {
    auto m = parse_machine(examples(std::string("machines/") + name + ".json"), name);
    ASSERT_TRUE(m.ok()) << name << ": " << m.error().message;
    EXPECT_EQ(m.value().name, name);
  }
  EXPECT_EQ(parse_machine(examples("machines/ded5_bc.json"), "bc").value().kind, Kinematics::kTableTiltB_RotaryC);
  EXPECT_EQ(parse_machine(examples("machines/gantry3.json"), "g").value().kind, Kinematics::k3Axis);
}

TEST(MachineConfig, P6UnknownAndDuplicateKeys) {
  EXPECT_NE(machine_error(edit(kAc, R"("c": {"continuous": true,)", R"("c": {"continous": true,)")).find("limits.c.continous"),
            std::string::npos);
  EXPECT_NE(machine_error(edit(kAc, R"("name")", R"("nmae")")).find("'nmae'"), std::string::npos);
  EXPECT_NE(machine_error(edit(kAc, R"("x_rot_point_mm": 0,)", R"("x_rot_point_mm": 0, "x_rot_point_mm": 1,)"))
                .find("x_rot_point_mm"),
            std::string::npos);
}

TEST(MachineConfig, P5NonFiniteNumbers) {
  // nlohmann reads 1e999 as inf: refused, naming the key.
  EXPECT_NE(machine_error(edit(kAc, R"("max": 120)", R"("max": 1e999)")).find("limits.a.max"), std::string::npos);
  EXPECT_NE(machine_error(edit(kAc, R"("max": 120)", R"("max": -1e999)")).find("limits.a.max"), std::string::npos);
  // JSON has no nan: a parse error, still bad usage.
  EXPECT_NE(machine_error(edit(kAc, R"("max": 120)", R"("max": nan)")).find("m.json"), std::string::npos);
  EXPECT_NE(machine_error(edit(kAc, R"("z_offset_mm": -80)", R"("z_offset_mm": 1e300)")).find("pivot.z_offset_mm"),
            std::string::npos);
  EXPECT_NE(machine_error(edit(kAc, R"("z_offset_mm": -80)", R"("z_offset_mm": "-80")")).find("must be a number"),
            std::string::npos);
}

TEST(MachineConfig, P3MinAboveMaxNamesBothKeys) {
  const std::string msg = machine_error(edit(kAc, R"("x": {"min": -400, "max": 400})", R"("x": {"min": 500, "max": 400})"));
  EXPECT_NE(msg.find("limits.x.min"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limits.x.max"), std::string::npos) << msg;
  EXPECT_NE(machine_error(edit(kAc, R"("linear_max_mm_min": 6000)", R"("linear_max_mm_min": 0)")).find("linear_max_mm_min"),
            std::string::npos);
}

TEST(MachineConfig, P4KinematicsAndAxes) {
  const std::string msg = machine_error(edit(kAc, "xyzac-trt", "xyzac-tcp"));
  EXPECT_NE(msg.find("xyzac-tcp"), std::string::npos);
  EXPECT_NE(msg.find("xyz, xyzac-trt, xyzbc-trt, xyzac-head, xyzbc-head"), std::string::npos) << msg;
  EXPECT_NE(machine_error(edit(kAc, R"(,
    "c": {"continuous": true, "unwind": false})", "")).find("limits.c"),
            std::string::npos);
  // A B limit on an A/C machine is an unknown axis.
  EXPECT_NE(machine_error(edit(kAc, R"("a": {)", R"("b": {)")).find("limits.b"), std::string::npos);
  // Offsets the kinematics does not use are refused rather than ignored.
  EXPECT_NE(machine_error(edit(kAc, R"("y_offset_mm": 0)", R"("x_offset_mm": 5)")).find("x_offset_mm"), std::string::npos);
  // C continuous and end stops at once is contradictory.
  EXPECT_NE(machine_error(edit(kAc, R"({"continuous": true,)", R"({"continuous": true, "max": 5,)")).find("limits.c"),
            std::string::npos);
  // Unwinding is asked of a continuous C; a C with end stops is always unwound.
  EXPECT_NE(machine_error(edit(kAc, R"({"continuous": true, "unwind": false})", R"({"min": -360, "max": 360, "unwind": true})"))
                .find("limits.c.unwind"),
            std::string::npos);
}

TEST(MachineConfig, HeadHeadNeedsItsPivotLengthAndNothingElse) {
  const std::string head = edit(edit(edit(kAc, "xyzac-trt", "xyzbc-head"), R"("a": {)", R"("b": {)"),
                                R"("pivot": {
    "x_rot_point_mm": 0,
    "y_rot_point_mm": 0,
    "z_rot_point_mm": 0,
    "y_offset_mm": 0,
    "z_offset_mm": -80,
    "tool_offset_mm": 0,
    "conventional_directions": false
  })",
                                R"("pivot": {"pivot_length_mm": 150})");
  auto m = parse_machine(head, "head.json");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m.value().kind, Kinematics::kHeadTiltB_RotaryC);
  EXPECT_EQ(tilt_axis_letter(m.value().kind), 'B');
  EXPECT_DOUBLE_EQ(m.value().pivot.pivot_length_mm, 150.0);
  EXPECT_NE(machine_error(edit(head, R"("pivot_length_mm": 150)", R"("pivot_length_mm": 0)")).find("pivot.pivot_length_mm"), std::string::npos);
  EXPECT_NE(machine_error(edit(head, R"({"pivot_length_mm": 150})", R"({"pivot_length_mm": 150, "z_offset_mm": 3})")).find("z_offset_mm"),
            std::string::npos);
  EXPECT_NE(machine_error(edit(head, R"(,
  "pivot": {"pivot_length_mm": 150})", "")).find("pivot_length_mm"),
            std::string::npos);
  // A table-table machine has no pivot length.
  EXPECT_NE(machine_error(edit(kAc, R"("tool_offset_mm": 0,)", R"("tool_offset_mm": 0, "pivot_length_mm": 150,)")).find("pivot_length_mm"),
            std::string::npos);
}

TEST(MachineConfig, UnwindingC) {
  auto m = parse_machine(edit(kAc, R"("unwind": false)", R"("unwind": true)"), "m.json");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_TRUE(m.value().c_unwind);
  EXPECT_TRUE(unwinds_c(m.value()));
  EXPECT_FALSE(unwinds_c(parse_machine(kAc, "m.json").value()));  // continuous, not asked
  EXPECT_TRUE(unwinds_c(parse_machine(examples("machines/ded5_bc.json"), "bc").value()));  // end stops
  EXPECT_FALSE(unwinds_c(parse_machine(examples("machines/gantry3.json"), "g").value()));   // no C
  // Whole turns toward 0 on a continuous C, with the coming sweep centred.
  EXPECT_DOUBLE_EQ(unwound_c_deg(m.value(), 725.0, 0.0, 0.0), 5.0);
  EXPECT_DOUBLE_EQ(unwound_c_deg(m.value(), -1075.0, 0.0, 0.0), 5.0);
  EXPECT_DOUBLE_EQ(unwound_c_deg(m.value(), 10.0, -360.0, 0.0), 10.0);
  EXPECT_DOUBLE_EQ(unwound_c_deg(m.value(), 10.0, -720.0, 0.0), 370.0);
  // On C in [-360, 360] a sweep of -400..0 from the start fits only from [40, 360].
  machine::MachineConfig lim = m.value();
  lim.c_continuous = false;
  lim.c_deg = {-360.0, 360.0};
  EXPECT_DOUBLE_EQ(unwound_c_deg(lim, -310.0, -400.0, 0.0), 50.0);
  EXPECT_DOUBLE_EQ(unwound_c_deg(lim, 770.0, 0.0, 300.0), -310.0);
}

TEST(MachineConfig, OverridesWithDottedKeys) {
  auto doc = parse_config_document(examples("machines/ded5_bc.json"), "bc");
  ASSERT_TRUE(doc.ok());
  ASSERT_TRUE(apply_override(doc.value(), "limits.c.max=360").ok());
  ASSERT_TRUE(apply_override(doc.value(), "pivot.conventional_directions=true").ok());
  ASSERT_TRUE(apply_override(doc.value(), "name=bc2").ok());
  auto m = parse_machine(doc.value().dump(), "bc+set");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m.value().c_deg.max, 360.0);
  EXPECT_TRUE(m.value().pivot.conventional_directions);
  EXPECT_EQ(m.value().name, "bc2");

  for (const char* bad : {"limits.c.mx=1", "limit.c.max=1", "limits.c.max", "limits.c=1", "limits.c.max=abc",
                          "pivot.conventional_directions=1", "limits.c.max=true"}) {
    const nlohmann::json before = doc.value();
    auto st = apply_override(doc.value(), bad);
    ASSERT_FALSE(st.ok()) << bad;
    EXPECT_EQ(st.error().code, ErrorCode::kUsage);
    EXPECT_NE(st.error().message.find(bad), std::string::npos) << st.error().message;
    EXPECT_EQ(doc.value(), before) << bad;
  }
  // An override to a non-finite value is refused at once (P5).
  auto inf = apply_override(doc.value(), "limits.c.max=1e999");
  ASSERT_FALSE(inf.ok());
  EXPECT_NE(inf.error().message.find("limits.c.max"), std::string::npos);
}

TEST(ProcessConfig, DefaultAndExample) {
  auto p = parse_process(default_process_json(), "default");
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p.value().name, "ded_steel");
  EXPECT_EQ(p.value().process_on, "M64 P0");
  EXPECT_EQ(p.value().self_supporting_deg, 30.0);
  EXPECT_EQ(examples("processes/ded_steel.json"), std::string(default_process_json()));
}

TEST(ProcessConfig, P1P2LayerHeight) {
  EXPECT_NE(process_error(edit(kProc, R"("layer_mm": 0.6)", R"("layer_mm": 0)")).find("layer_mm"), std::string::npos);
  EXPECT_NE(process_error(edit(kProc, R"("layer_min_mm": 0.3)", R"("layer_min_mm": -0.5)")).find("layer_min_mm"),
            std::string::npos);
  // 0.8 · 0.9 mm bead = 0.72 mm.
  const std::string msg = process_error(edit(kProc, R"("layer_max_mm": 0.7)", R"("layer_max_mm": 0.73)"));
  EXPECT_NE(msg.find("layer_max_mm"), std::string::npos);
  EXPECT_NE(msg.find("0.72"), std::string::npos) << msg;
  EXPECT_TRUE(parse_process(edit(kProc, R"("layer_max_mm": 0.7)", R"("layer_max_mm": 0.72)"), "p").ok());
}

TEST(ProcessConfig, P3P5P6) {
  const std::string msg = process_error(edit(kProc, R"("layer_min_mm": 0.3)", R"("layer_min_mm": 0.71)"));
  EXPECT_NE(msg.find("layer_min_mm"), std::string::npos);
  EXPECT_NE(msg.find("layer_max_mm"), std::string::npos) << msg;
  EXPECT_NE(process_error(edit(kProc, R"("dwell_on_s": 0.5)", R"("dwell_on_s": 1e999)")).find("dwell_on_s"),
            std::string::npos);
  EXPECT_NE(process_error(edit(kProc, R"("dwell_on_s")", R"("dwell_s")")).find("dwell_s"), std::string::npos);
  EXPECT_NE(process_error(edit(kProc, R"("M64 P0")", R"x("M64 P0 (on)")x")).find("process_on"), std::string::npos);
  EXPECT_NE(process_error(edit(kProc, R"("M65 P0")", R"("M64 P0")")).find("differ"), std::string::npos);
  EXPECT_NE(process_error(edit(kProc, R"("travel_feed_mm_s": 50)", R"("travel_feed_mm_s": -1)")).find("travel_feed_mm_s"),
            std::string::npos);
}

}  // namespace
}  // namespace polyaxis::machine
