// The 3MF toolpath post (post/toolpath_3mf.h): the package validates against the Toolpath
// Extension's schema (tests/schema/toolpath_3mf.xsd, and the specification's own XSD when
// POLYAXIS_TOOLPATH_XSD names it) and its prose rules; it reads back onto the plan through the
// library's reader (simulate) and the tests' own (toolpath_3mf_replay.h); feeds the axes slow are
// the depositionspeed modifier's factor; identical input gives identical bytes; the set id; and
// what the writer and the reader refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <regex>

#include "polyaxis/io/zip_archive.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/post/toolpath_3mf.h"
#include "polyaxis/post/traori.h"
#include "polyaxis/verify/simulate.h"
#include "support/programs.h"
#include "support/toolpath_3mf_replay.h"
#include "support/toolpath_3mf_schema.h"

namespace polyaxis::post {
namespace {

using namespace polyaxis::test;

machine::MachineConfig toolpath_machine() {
  machine::MachineConfig m = example_machine("ded5_ac");
  m.post = machine::PostDialect::k3mfToolpath;
  return m;
}

mesh::Mesh cube() {
  mesh::Mesh c;
  for (int k = 0; k < 8; ++k) c.vertices.push_back({(k & 1) ? 20.0 : 0.0, (k & 2) ? 20.0 : 0.0, (k & 4) ? 2.0 : 0.0});
  c.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return c;
}

// Two layers of a square with the torch tilted on two sides, a turn in place with the process on,
// travel between them and away.
std::vector<ProgramPoint> squares() {
  const double s = std::sin(M_PI / 6.0), c = std::cos(M_PI / 6.0);
  std::vector<ProgramPoint> p;
  auto add = [&](core::Vec3 tip, core::Vec3 axis, bool on, std::uint32_t layer, double feed = 8.0) {
    ProgramPoint q;
    q.tip_part_mm = tip, q.tool_axis_part = axis, q.process_on = on, q.feed_mm_s = feed, q.layer = layer, q.region = 1;
    p.push_back(q);
  };
  for (std::uint32_t layer = 0; layer < 2; ++layer) {
    const double z = 1.0 + 0.6 * layer;
    add({0, 0, z + 5}, {0, 0, 1}, false, layer, 50.0);
    p.back().comment_if_new_block = "approach";
    add({0, 0, z}, {0, 0, 1}, false, layer, 50.0);
    add({20, 0, z}, {0, -s, c}, true, layer);
    p.back().comment_if_new_block = "perimeter 0";
    add({20, 20, z}, {s, 0, c}, true, layer);
    add({0, 20, z}, {0, 0, 1}, true, layer);
    add({0, 0, z}, {0, 0, 1}, true, layer);
    add({0, 0, z}, {-s, 0, c}, true, layer);  // turn in place: the process must not stay on
    add({5, 5, z}, {-s, 0, c}, true, layer);
  }
  add({0, 0, 20}, {0, 0, 1}, false, 1, 50.0);
  return p;
}

const mesh::Mesh& part() {
  static const mesh::Mesh c = cube();
  return c;
}

GcodeOptions with_part() {
  GcodeOptions o;
  o.part = &part();
  return o;
}

std::string package_of(const std::vector<ProgramPoint>& points, const machine::MachineConfig& m = toolpath_machine()) {
  auto out = write_program(m, default_process(), points, with_part());
  EXPECT_TRUE(out.ok()) << out.error().message;
  return out.ok() ? out.value() : std::string();
}

TEST(Toolpath3mf, ValidatesAgainstTheSchemaAndItsProseRules) {
  const std::string package = package_of(squares());
  EXPECT_EQ(program_extension(toolpath_machine()), ".build.3mf");
  auto parts = zip_parts(package);
  EXPECT_EQ(toolpath_schema_errors(std::string(POLYAXIS_SCHEMA_DIR) + "/toolpath_3mf.xsd", parts), 0);
  if (const char* official = std::getenv("POLYAXIS_TOOLPATH_XSD"); official != nullptr && *official != '\0') {
    EXPECT_EQ(toolpath_schema_errors(official, parts), 0) << official;
  }
  const std::string& model = parts["3D/3dmodel.model"];
  EXPECT_NE(model.find("requiredextensions=\"p tp\""), std::string::npos);
  EXPECT_NE(model.find("toolpathtype=\"6axis\""), std::string::npos);
  EXPECT_NE(model.find("tp:toolpathid=\"1\""), std::string::npos);
  EXPECT_TRUE(parts.count("[Content_Types].xml") == 1 && parts.count("_rels/.rels") == 1);
  // Every layer path is the target of a layer relationship of the model part, and nothing else is.
  std::smatch m;
  std::vector<std::string> paths, targets;
  const std::string& rels = parts["3D/_rels/3dmodel.model.rels"];
  const std::regex layer_re(R"~(toolpathlayer path="([^"]+)")~");
  for (auto it = std::sregex_iterator(model.begin(), model.end(), layer_re); it != std::sregex_iterator(); ++it) {
    paths.push_back((*it)[1]);
  }
  const std::regex rel_re("Target=\"([^\"]+)\" Id=\"[^\"]+\" Type=\"" + std::string(kToolpathLayerRelationship) + "\"");
  for (auto it = std::sregex_iterator(rels.begin(), rels.end(), rel_re); it != std::sregex_iterator(); ++it) targets.push_back((*it)[1]);
  EXPECT_EQ(paths, targets);
  EXPECT_EQ(paths.size(), 2u);  // one part per layer of the program
  // The layer parts name the build item's UUID and the profile's; every segment has two or more points.
  ASSERT_TRUE(std::regex_search(model, m, std::regex(R"~(<item objectid="2" p:UUID="([^"]+)")~")));
  const std::string item = m[1];
  ASSERT_TRUE(std::regex_search(model, m, std::regex(R"~(<tp:toolpathprofile uuid="([^"]+)")~")));
  const std::string profile = m[1];
  for (const std::string& path : paths) {
    const std::string& layer = parts[path.substr(1)];
    EXPECT_NE(layer.find("<part id=\"1\" uuid=\"" + item + "\"/>"), std::string::npos) << path;
    EXPECT_NE(layer.find("<profile id=\"1\" uuid=\"" + profile + "\"/>"), std::string::npos) << path;
    const std::regex seg(R"~(<segment type="polyline6d" profileid="1" partid="1">([\s\S]*?)</segment>)~");
    int segments = 0;
    for (auto it = std::sregex_iterator(layer.begin(), layer.end(), seg); it != std::sregex_iterator(); ++it, ++segments) {
      const std::string body = (*it)[1];
      const std::regex point("<point6d ");
      EXPECT_GE(std::distance(std::sregex_iterator(body.begin(), body.end(), point), std::sregex_iterator()), 2);
    }
    EXPECT_EQ(segments, 2) << path;  // the square, then the bead after the turn in place
  }
}

TEST(Toolpath3mf, ReadsBackOntoThePlanThroughBothReaders) {
  const auto m = toolpath_machine();
  const auto p = default_process();
  const auto points = squares();
  const std::string package = package_of(points, m);
  auto sim = verify::simulate(m, package, points, &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u);
  EXPECT_LE(sim.value().max_tip_deviation_mm, 0.01);
  EXPECT_GT(sim.value().moves, 10u);
  // The tests' reader: every program point, in order, within 0.2 µm and 1e-6 of a pose read back.
  const Replay3mf r = replay_toolpath_3mf(package, p);
  EXPECT_LE(r.worst_quaternion_norm_error, 1e-8);
  std::size_t at = 0;
  for (const ProgramPoint& pt : points) {
    while (at < r.tips.size() && !(core::norm(r.tips[at] - pt.tip_part_mm) <= 2e-4 && core::norm(r.axes[at] - core::normalized(pt.tool_axis_part)) <= 1e-6)) {
      ++at;
    }
    EXPECT_LT(at, r.tips.size()) << "program point not read back: " << pt.tip_part_mm.x << " " << pt.tip_part_mm.y << " " << pt.tip_part_mm.z;
  }
  // The turn in place is travel: the process is off while the tool turns.
  const std::string& t = r.traori;
  const std::size_t turn = t.find("A3=-0.5");
  ASSERT_NE(turn, std::string::npos);
  EXPECT_LT(t.rfind(p.process_off, turn), turn);
  EXPECT_GT(t.rfind(p.process_off, turn), t.rfind(p.process_on, turn));
}

TEST(Toolpath3mf, FeedsTheAxesSlowAreTheModifiersFactor) {
  auto m = toolpath_machine();
  m.feed.linear_max_mm_min = 400.0;  // below the deposit feed's 480 mm/min: the beads slow, not enough to split
  const auto p = default_process();
  const auto points = squares();
  const std::string package = package_of(points, m);
  const std::string model = zip_parts(package)["3D/3dmodel.model"];
  EXPECT_NE(model.find("<tp:modifier attribute=\"depositionspeed\" type=\"constant\" factor=\"f\""), std::string::npos);
  auto sim = verify::simulate(m, package, points, &p, 0.01);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  EXPECT_EQ(sim.value().limit_violations, 0u) << (sim.value().violations.empty() ? "" : sim.value().violations.front());
  // Without the slowing (the default machine), no modifier.
  EXPECT_EQ(zip_parts(package_of(points))["3D/3dmodel.model"].find("tp:modifier"), std::string::npos);
}

TEST(Toolpath3mf, SameInputSameBytesAndTheSetId) {
  const auto m = toolpath_machine();
  const std::string a = package_of(squares()), b = package_of(squares());
  EXPECT_EQ(a, b);
  auto stamped = with_set_id(m, a, "0123456789abcdef");
  ASSERT_TRUE(stamped.ok()) << stamped.error().message;
  auto parts = zip_parts(stamped.value());
  EXPECT_NE(parts["3D/3dmodel.model"].find("<metadata name=\"pa:set\">0123456789abcdef</metadata>"), std::string::npos);
  EXPECT_EQ(parts["Toolpath/Layers/layer00001.xml"], zip_parts(a)["Toolpath/Layers/layer00001.xml"]);
  const auto p = default_process();
  EXPECT_EQ(replay_toolpath_3mf(stamped.value(), p).traori, replay_toolpath_3mf(a, p).traori);
  // The text posts: the id in the first comment, the line count kept.
  auto gcode = with_set_id(example_machine("ded5_ac"), "(polyaxis: x)\nG21\n", "42");
  ASSERT_TRUE(gcode.ok());
  EXPECT_EQ(gcode.value(), "(polyaxis: x, set 42)\nG21\n");
}

TEST(Toolpath3mf, RefusesWhatItCannotWrite) {
  const auto m = toolpath_machine();
  const auto p = default_process();
  auto no_part = write_program(m, p, squares());
  ASSERT_FALSE(no_part.ok());
  EXPECT_EQ(no_part.error().code, core::ErrorCode::kUsage);
  auto far = squares();
  far[3].tip_part_mm.x = 3e6;
  auto beyond = write_toolpath_3mf(m, p, far, with_part());
  ASSERT_FALSE(beyond.ok());
  EXPECT_NE(beyond.error().message.find("214 m "), std::string::npos) << beyond.error().message;
  auto down = squares();
  down[3].tool_axis_part = {0, 0, -1};  // the table cannot turn the torch to point up at the part
  auto unreachable = write_toolpath_3mf(m, p, down, with_part());
  ASSERT_FALSE(unreachable.ok());
  EXPECT_EQ(unreachable.error().code, core::ErrorCode::kMachineLimit);
}

// A copy of PACKAGE with FROM replaced by TO in the part PATH.
std::string edited(const std::string& package, const std::string& path, const std::string& from, const std::string& to) {
  std::string part = zip_parts(package)[path];
  const std::size_t at = part.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) part.replace(at, from.size(), to);
  auto out = io::replace_zip_entry(package, path, part);
  EXPECT_TRUE(out.ok());
  return out.ok() ? out.value() : std::string();
}

TEST(Toolpath3mf, TheReaderRefusesBrokenPackagesNamingWhy) {
  const auto m = toolpath_machine();
  const std::string good = package_of(squares());
  const std::string layer = "Toolpath/Layers/layer00001.xml", model = "3D/3dmodel.model";
  struct Case {
    std::string package, expect;
  };
  const std::vector<Case> cases = {
      {"not a zip archive at all, just text", "not a zip archive"},
      {edited(good, "3D/_rels/3dmodel.model.rels", "layer00001.xml\" Id", "layer09999.xml\" Id"), "not the target of a toolpath layer relationship"},
      {edited(good, layer, "profileid=\"1\"", "profileid=\"7\""), "names no profile"},
      {edited(good, layer, "partid=\"1\"", "partid=\"3\""), "names no part"},
      {edited(good, model, "toolpathtype=\"6axis\"", "toolpathtype=\"planar\""), "toolpathtype 'planar' is not read"},
      {edited(good, layer, "i=\"", "i=\"x"), "quaternion i"},
      {edited(good, layer, "<segments>", "<segments><segment type=\"polyline6d\" profileid=\"1\" partid=\"1\"><point6d x=\"0\" y=\"0\" z=\"0\" i=\"0\" j=\"0\" k=\"0\" w=\"1\"/></segment>"),
       "two or more points"},
      {edited(good, layer, "<segments>", "<segments><segment type=\"polyline6d\" profileid=\"1\" partid=\"1\"><point6d x=\"0\" y=\"0\" z=\"1000\" i=\"0\" j=\"0\" k=\"0\" w=\"0\"/>"
                                          "<point6d x=\"0\" y=\"0\" z=\"1000\" i=\"0\" j=\"0\" k=\"0\" w=\"1\"/></segment>"),
       "cannot be normalised"},
      {edited(good, layer, "</layer>", "<layer>"), "not well-formed XML"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    auto sim = verify::simulate(m, cases[k].package, {}, nullptr, 0.01);
    ASSERT_FALSE(sim.ok()) << k;
    EXPECT_EQ(sim.error().code, core::ErrorCode::kInvalidInput) << k << ": " << sim.error().message;
    EXPECT_NE(sim.error().message.find(cases[k].expect), std::string::npos) << k << ": " << sim.error().message;
  }
  // A modifier the reader does not support is refused (spec §4.2: reject what cannot be executed).
  auto slow = m;
  slow.feed.linear_max_mm_min = 400.0;
  const std::string linear = edited(package_of(squares(), slow), model, "type=\"constant\"", "type=\"linear\"");
  auto sim = verify::simulate(slow, linear, {}, nullptr, 0.01);
  ASSERT_FALSE(sim.ok());
  EXPECT_NE(sim.error().message.find("modifier polyaxis does not support"), std::string::npos) << sim.error().message;
}

}  // namespace
}  // namespace polyaxis::post
