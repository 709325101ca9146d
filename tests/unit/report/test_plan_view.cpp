// plan.json written and read back, the viewer's data (base64 arrays, decimation, layer ranges) and
// the report page's escaping.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/repair.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "polyaxis/report/plan_view.h"
#include "polyaxis/report/report_html.h"

namespace polyaxis::report {
namespace {

mesh::Mesh cube(double s) {
  mesh::Mesh m;
  m.vertices = {{0, 0, 0}, {s, 0, 0}, {s, s, 0}, {0, s, 0}, {0, 0, s}, {s, 0, s}, {s, s, s}, {0, s, s}};
  m.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                 {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return m;
}

// A small view by hand: two regions, an axis, two layers, a program alternating travel and deposit.
PlanView small_view(std::size_t program_points = 6) {
  PlanView v;
  v.part = "parts/cube.stl";
  v.machine = "ded5_ac";
  v.kinematics = "xyzac-trt";
  v.tilt_axis = "A";
  v.process = "ded_steel";
  v.bead_width_mm = 0.9;
  v.placement.translation_mm = {-5, -5, 0};
  v.metrics_json = R"({"layers": 2, "support_free": false, "timings_s": {"read": 0.5}})";
  planner::PlanRegion root;
  root.mesh = cube(10);
  planner::PlanRegion child;
  child.id = 1, child.parent = 0, child.mesh = cube(2), child.direction = {1, 0, 0}, child.base_point = {10, 5, 5};
  child.support_free = false;
  v.regions = {root, child};
  v.axis = ViewAxis{{{5, 5, 0}, {5, 5, 5}, {9, 5, 5}}, {{{0, 1, 0}}, {{1, 2, 1}}}};
  for (std::uint32_t k = 0; k < 2; ++k) {
    ViewLayer l;
    l.index = k;
    l.region = k;
    l.origin = {0, 0, 0.3 + k};
    l.thickness_mm = 0.6;
    l.area_mm2 = 100;
    l.tilt_deg = {0, 12.5};
    l.c_deg = {-90, 45};
    l.contours = {{{0, 0, l.origin.z}, {10, 0, l.origin.z}, {10, 10, l.origin.z}}};
    if (k == 1) l.unsupported = {{{1, 1, 1.3}, {2, 1, 1.3}, {2, 2, 1.3}}}, l.unsupported_area_mm2 = 0.5;
    v.layers.push_back(l);
  }
  for (std::size_t i = 0; i < program_points; ++i) {
    post::ProgramPoint p;
    p.tip_part_mm = {static_cast<double>(i), 1.0, 0.3};
    p.tool_axis_part = {0, 0, 1};
    p.feed_mm_s = 10;
    p.process_on = (i / 3) % 2 == 1;
    p.layer = i < program_points / 2 ? 0 : 1;
    p.region = p.layer;
    v.program.push_back(p);
  }
  v.collisions.push_back({{3.0, 1.0, 5.5}, "layer 1 region 1, line 40: the head strikes the deposit of layer 0 region 0 (0.40 mm) \"<\\/script>\""});
  return v;
}

std::vector<unsigned char> unbase64(const std::string& s) {
  std::vector<unsigned char> out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    int d = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52 : c == '+' ? 62 : c == '/' ? 63 : -1;
    if (d < 0) continue;
    acc = (acc << 6) | static_cast<std::uint32_t>(d), bits += 6;
    if (bits >= 8) bits -= 8, out.push_back(static_cast<unsigned char>((acc >> bits) & 0xff));
  }
  return out;
}

template <typename T>
std::vector<T> typed(const std::string& b64) {
  const auto bytes = unbase64(b64);
  EXPECT_EQ(bytes.size() % sizeof(T), 0u);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

TEST(PlanView, JsonReadsBackWhatWasWritten) {
  const PlanView v = small_view();
  const std::string text = plan_view_json(v);
  EXPECT_EQ(text, plan_view_json(v));  // deterministic
  auto back = read_plan_view(text, "plan.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  const PlanView& b = back.value();
  EXPECT_EQ(b.part, v.part);
  EXPECT_EQ(b.tilt_axis, "A");
  ASSERT_EQ(b.regions.size(), 2u);
  EXPECT_FALSE(b.regions[0].parent.has_value());
  EXPECT_EQ(b.regions[1].parent, 0u);
  EXPECT_FALSE(b.regions[1].support_free);
  EXPECT_EQ(b.regions[1].mesh.triangles, v.regions[1].mesh.triangles);
  EXPECT_NEAR(b.regions[1].base_point.x, 10.0, 1e-9);
  ASSERT_TRUE(b.axis.has_value());
  EXPECT_EQ(b.axis->links[1][2], 1u);
  ASSERT_EQ(b.layers.size(), 2u);
  EXPECT_NEAR(b.layers[1].c_deg[0], -90.0, 1e-9);
  EXPECT_NEAR(b.layers[0].tilt_deg[1], 12.5, 1e-9);
  ASSERT_EQ(b.layers[1].unsupported.size(), 1u);
  EXPECT_NEAR(b.layers[1].unsupported[0][2].y, 2.0, 1e-9);
  EXPECT_EQ(b.program.size(), v.program.size());
  EXPECT_TRUE(b.program[3].process_on);
  EXPECT_EQ(nlohmann::json::parse(b.metrics_json)["timings_s"]["read"].get<double>(), 0.5);
  ASSERT_EQ(b.collisions.size(), 1u);
  EXPECT_EQ(b.collisions[0].what, v.collisions[0].what);
  EXPECT_NEAR(b.collisions[0].position.z, 5.5, 1e-9);
  EXPECT_EQ(plan_view_json(b), text);  // a second round trip changes nothing
  auto program = read_plan_program(text, "plan.json");
  ASSERT_TRUE(program.ok());
  EXPECT_EQ(program.value().size(), v.program.size());
}

TEST(PlanView, MalformedPlansAreInvalidInputNamingTheFile) {
  const std::string good = plan_view_json(small_view());
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  for (const std::string& bad : {std::string("not json"), std::string("{}"), replaced("polyaxis-plan/1", "polyaxis-plan/9"),
                                 replaced("\"triangles\":[0,2,1", "\"triangles\":[0,2,99"), replaced("\"c_deg\":[", "\"c_deg\":[1,"),
                                 replaced(",1,1,1]", ",1,7,1]"), replaced("\"bead_width_mm\":0.9", "\"bead_width_mm\":\"x\""),
                                 // Ids that are no unsigned integers (fuzz_plan_json: get<uint32_t> of -24.9995 was UB).
                                 replaced("\"triangles\":[0,2,1", "\"triangles\":[0,-24.9995,1"),
                                 replaced("\"triangles\":[0,2,1", "\"triangles\":[0,2.5,1"),
                                 replaced("\"triangles\":[0,2,1", "\"triangles\":[0,4294967296,1"),
                                 good.substr(0, good.size() / 2)}) {
    auto r = read_plan_view(bad, "some/plan.json");
    ASSERT_FALSE(r.ok()) << bad.substr(0, 80);
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_NE(r.error().message.find("some/plan.json"), std::string::npos) << r.error().message;
  }
}

TEST(ViewData, ArraysDecodeToTheViewAndLayersIndexTheirPoints) {
  const PlanView v = small_view(10);
  const auto data = nlohmann::json::parse(view_data_json(v));
  EXPECT_EQ(data["format"], "polyaxis-view/1");
  EXPECT_EQ(data["machine"]["tilt_axis"], "A");
  EXPECT_FALSE(data["metrics"]["support_free"].get<bool>());
  const auto positions = typed<float>(data["regions"][1]["positions"]);
  ASSERT_EQ(positions.size(), 24u);
  EXPECT_FLOAT_EQ(positions[3 * 6 + 0], 2.0f);  // vertex 6 of the 2 mm cube
  EXPECT_EQ(typed<std::uint32_t>(data["regions"][0]["indices"]).size(), 36u);
  const auto points = typed<float>(data["toolpath"]["points"]);
  const auto flags = typed<std::uint8_t>(data["toolpath"]["flags"]);
  ASSERT_EQ(points.size(), 30u);
  ASSERT_EQ(flags.size(), 10u);
  EXPECT_EQ(flags[0], 2);   // the first point starts the path, arriving by travel
  EXPECT_EQ(flags[3], 1);   // points 3-5 deposit
  EXPECT_EQ(flags[6], 0);
  EXPECT_EQ(data["layers"][0]["path_first"], 0);
  EXPECT_EQ(data["layers"][0]["path_count"], 5);
  EXPECT_EQ(data["layers"][1]["path_first"], 5);
  EXPECT_EQ(data["layers"][1]["path_count"], 5);
  EXPECT_EQ(typed<float>(data["layers"][1]["unsupported"]).size(), 9u);
  EXPECT_EQ(data["layers"][1]["contour_starts"], nlohmann::json::array({0}));
  EXPECT_EQ(data["layers"][0]["unsupported"], "");
  // Collisions go to the viewer as points with what was struck (drawn red and listed).
  ASSERT_EQ(data["collisions"].size(), 1u);
  EXPECT_EQ(data["collisions"][0]["position"][2].get<double>(), 5.5);
  EXPECT_NE(data["collisions"][0]["what"].get<std::string>().find("deposit of layer 0"), std::string::npos);
}

TEST(ViewData, BigProgramsAreDecimatedKeepingEveryRunsEnds) {
  PlanView v = small_view(0);
  for (std::size_t i = 0; i < 100'000; ++i) {
    post::ProgramPoint p;
    const double t = static_cast<double>(i) * 1e-3;
    p.tip_part_mm = {std::cos(t), std::sin(t), 0.3};
    p.tool_axis_part = {0, 0, 1};
    p.feed_mm_s = 10;
    p.process_on = (i / 1000) % 2 == 1;  // runs of 1000 points
    p.layer = i < 50'000 ? 0 : 1;
    v.program.push_back(p);
  }
  HtmlOptions options;
  options.max_points = 5000;
  const auto data = nlohmann::json::parse(view_data_json(v, options));
  const std::size_t shown = data["toolpath"]["shown_points"].get<std::size_t>();
  EXPECT_EQ(data["toolpath"]["total_points"], 100000);
  EXPECT_LE(shown, 5000u + 2 * 100);  // the stride, plus each run's two ends
  EXPECT_GE(shown, 4000u);
  const auto flags = typed<std::uint8_t>(data["toolpath"]["flags"]);
  const auto points = typed<float>(data["toolpath"]["points"]);
  ASSERT_EQ(flags.size(), shown);
  // Every run is still there with both ends: 100 runs, so 99 changes of the deposit bit.
  int changes = 0;
  for (std::size_t i = 1; i < flags.size(); ++i) changes += (flags[i] & 1) != (flags[i - 1] & 1);
  EXPECT_EQ(changes, 99);
  EXPECT_FLOAT_EQ(points[3 * (shown - 1)], static_cast<float>(std::cos(99'999e-3)));
  EXPECT_EQ(data["layers"][0]["path_count"].get<std::size_t>() + data["layers"][1]["path_count"].get<std::size_t>(), shown);
}

TEST(ReportHtml, NeitherDataNorScriptCanCloseTheirElement) {
  PlanView v = small_view();
  v.part = "dir/evil<b>&.stl";
  v.machine = "m</script><script>alert(1)</script><!--<script>";
  const std::string html = report_html(v, "var s = '</script>'; var t = a</b;");
  std::size_t closers = 0;
  for (std::size_t at = html.find("</script>"); at != std::string::npos; at = html.find("</script>", at + 1)) ++closers;
  EXPECT_EQ(closers, 2u);  // the data element's and the script element's own
  EXPECT_EQ(html.find("<!--"), std::string::npos);
  EXPECT_NE(html.find("var s = '<\\/script>'; var t = a</b;"), std::string::npos);  // only "</script" is touched in code
  EXPECT_NE(html.find("<title>polyaxis — evil&lt;b>&amp;.stl</title>"), std::string::npos);
  // The data element's text is the JSON the viewer reads.
  const auto start = html.find("id=\"polyaxis-data\">") + std::strlen("id=\"polyaxis-data\">");
  const auto data = nlohmann::json::parse(html.substr(start, html.find("</script>", start) - start));
  EXPECT_EQ(data["title"], v.part);
  EXPECT_EQ(data["machine"]["name"], v.machine);
}

TEST(ReportHtml, TheCompiledViewerBundleIsThere) {
  const std::string_view bundle = viewer_bundle();
  EXPECT_GT(bundle.size(), 100'000u);  // three.js and the viewer, minified
  EXPECT_NE(bundle.find("polyaxis-data"), std::string_view::npos);
}

TEST(PlanView, RealPlanHasContoursRotaryRangesAndTheWholePartAsOneRegion) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/pen_rack.stl");
  ASSERT_TRUE(read.ok());
  auto part = mesh::repair(std::move(read.value().mesh));
  ASSERT_TRUE(part.ok());
  const machine::MachineConfig machine = machine::parse_machine(machine::default_machine_json(), "default").value();
  const process::ProcessConfig process = process::parse_process(process::default_process_json(), "default").value();
  auto plan = planner::make_plan(part.value(), machine, process, {});
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  const PlanView v = make_plan_view(plan.value(), machine, process, nullptr, "pen_rack.stl", "{}");
  ASSERT_EQ(v.regions.size(), 1u);
  EXPECT_EQ(v.regions[0].support_free, plan.value().unsupported_area_mm2 == 0.0);
  EXPECT_FALSE(v.axis.has_value());
  ASSERT_EQ(v.layers.size(), plan.value().layers.layers.size());
  double largest_tilt = 0.0;
  for (const ViewLayer& l : v.layers) {
    EXPECT_FALSE(l.contours.empty()) << "layer " << l.index;
    for (const auto& ring : l.contours) {
      for (const Vec3& p : ring) EXPECT_NEAR(core::dot(p - l.origin, l.normal), 0.0, 1e-6);  // on the layer's plane
    }
    largest_tilt = std::max(largest_tilt, std::max(std::fabs(l.tilt_deg[0]), std::fabs(l.tilt_deg[1])));
    EXPECT_LE(l.tilt_deg[0], l.tilt_deg[1]);
    EXPECT_EQ(l.unsupported.empty(), l.unsupported_area_mm2 == 0.0) << "layer " << l.index;
  }
  // The leaning bar is built with the torch tilted on its overhanging side: the table tilts.
  EXPECT_GT(largest_tilt, 1.0);
  EXPECT_NEAR(largest_tilt, plan.value().max_tilt_deg, 1.0);
}

}  // namespace
}  // namespace polyaxis::report
