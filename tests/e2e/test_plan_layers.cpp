// Tilted "3-D" layers end to end (issue 13, items 1 and 4): `polyaxis plan --layers tilted` on bars
// bent through several angles, radii and tessellations, judged from the G-code alone: each
// layer's deposit lies on a plane, consecutive planes turn, and the thickness at every deposit
// point (the distance along the tool axis, read through forward kinematics, down to the plane
// fitted to the region's previous layer) stays in the process's range; the program reads back
// clean (plate, table, grounding, collisions) and rs274 accepts it. `--layers auto` (the default)
// takes tilted layers where planar ones overhang and keeps planar ones where the tilted head would
// strike the plate.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>

#include "polyaxis/machine/kinematics.h"
#include "support/cli.h"
#include "support/meshes.h"
#include "support/plan_checks.h"

namespace polyaxis::test {
namespace {

using core::Vec3;

struct Deposit {
  Vec3 tip, axis;
};

struct LayerDeposit {
  int region = -1;
  std::vector<Deposit> points;
};

// The end points of the process-on feed blocks of GCODE, by layer, through forward kinematics on the
// default machine (the plan's part frame).
std::map<int, LayerDeposit> deposits(const std::string& gcode) {
  auto m = machine::parse_machine(machine::default_machine_json(), "default");
  auto p = process::parse_process(process::default_process_json(), "default");
  EXPECT_TRUE(m.ok() && p.ok());
  std::map<int, LayerDeposit> out;
  std::istringstream in(gcode);
  std::string line;
  std::array<double, 6> pos{};
  bool on = false;
  int layer = -1, region = -1;
  const std::regex comment(R"(^\(layer (\d+) region (\d+))");
  std::smatch mt;
  const std::string letters = "XYZABC";
  while (std::getline(in, line)) {
    if (std::regex_search(line, mt, comment)) layer = std::stoi(mt[1]), region = std::stoi(mt[2]);
    if (line == p.value().process_on) on = true;
    if (line == p.value().process_off) on = false;
    if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
    for (std::size_t i = 0; i < 6; ++i) {
      if (const auto at = line.find(letters[i]); at != std::string::npos) pos[i] = std::stod(line.substr(at + 1));
    }
    if (!on || line[1] != '1') continue;
    const machine::MachineToolPose tp = machine::forward(m.value(), {pos[0], pos[1], pos[2], pos[3], pos[5]});
    LayerDeposit& l = out[layer];
    l.region = region;
    l.points.push_back({tp.tip_part_mm, core::normalized(tp.tool_axis_part)});
  }
  return out;
}

struct Plane {
  Vec3 point, normal;
  double spread_mm = 0.0;  // the largest distance of a fitted point from the plane
};

// The least-squares plane through POINTS, as a height over the plane square to REF (the layer's
// mean tool axis: a layer's points are spread across it).
Plane fit(const std::vector<Deposit>& points, Vec3 ref) {
  ref = core::normalized(ref);
  const Vec3 e1 = core::normalized(std::fabs(ref.x) < 0.9 ? core::cross(ref, {1, 0, 0}) : core::cross(ref, {0, 1, 0}));
  const Vec3 e2 = core::cross(ref, e1);
  Vec3 mean;
  for (const Deposit& d : points) mean = mean + d.tip;
  mean = mean / static_cast<double>(points.size());
  // h = a·x + b·y over (x, y) = ((p − mean)·e1, (p − mean)·e2): normal equations.
  double sxx = 0, sxy = 0, syy = 0, sxh = 0, syh = 0;
  for (const Deposit& d : points) {
    const Vec3 q = d.tip - mean;
    const double x = core::dot(q, e1), y = core::dot(q, e2), h = core::dot(q, ref);
    sxx += x * x, sxy += x * y, syy += y * y, sxh += x * h, syh += y * h;
  }
  const double det = sxx * syy - sxy * sxy;
  const double a = det != 0.0 ? (sxh * syy - syh * sxy) / det : 0.0, b = det != 0.0 ? (syh * sxx - sxh * sxy) / det : 0.0;
  Plane plane{mean, core::normalized(ref - e1 * a - e2 * b)};
  for (const Deposit& d : points) plane.spread_mm = std::max(plane.spread_mm, std::fabs(core::dot(d.tip - mean, plane.normal)));
  return plane;
}

struct Thickness {
  double least = INFINITY, most = 0.0;
  double largest_turn_deg = 0.0;  // between consecutive layers' planes
  double largest_spread_mm = 0.0;  // of a layer's points off its plane
  std::size_t measured = 0;
};

// Every deposit point after its region's first layer, against the plane of the region's layer before.
Thickness thickness(const std::map<int, LayerDeposit>& layers) {
  Thickness t;
  std::map<int, Plane> last;  // region -> its latest layer's plane
  for (const auto& [index, l] : layers) {
    if (l.points.size() < 3) continue;
    Vec3 mean_axis;
    for (const Deposit& d : l.points) mean_axis = mean_axis + d.axis;
    const Plane plane = fit(l.points, mean_axis);
    t.largest_spread_mm = std::max(t.largest_spread_mm, plane.spread_mm);
    if (const auto it = last.find(l.region); it != last.end()) {
      const Plane& below = it->second;
      t.largest_turn_deg = std::max(t.largest_turn_deg, std::acos(std::clamp(core::dot(below.normal, plane.normal), -1.0, 1.0)) * 180.0 / M_PI);
      for (const Deposit& d : l.points) {
        const double along = core::dot(d.axis, below.normal);
        if (along <= 0.0) continue;
        const double h = core::dot(d.tip - below.point, below.normal) / along;  // along the tool axis down to the plane
        t.least = std::min(t.least, h), t.most = std::max(t.most, h);
        ++t.measured;
      }
    }
    last[l.region] = plane;
  }
  return t;
}

struct Bend {
  double r_bend, r_bar, sweep_deg;
  unsigned n, m;
};

TEST(PlanLayers, TiltedLayersOnBentBarsKeepTheThicknessInRangeAndReadBackClean) {
  auto proc = process::parse_process(process::default_process_json(), "default");
  ASSERT_TRUE(proc.ok());
  // Path words are rounded to 1e-4 mm and the tip follows the path within 0.01 mm.
  constexpr double kSlackMm = 0.02;
  for (const Bend b : {Bend{60, 6, 70, 40, 24}, Bend{45, 7, 80, 36, 16}, Bend{90, 5, 55, 70, 20}}) {
    const std::string name = fmt::format("bar_{:.0f}_{:.0f}_{:.0f}", b.r_bend, b.r_bar, b.sweep_deg);
    SCOPED_TRACE(name);
    TempDir dir;
    const auto stl = dir / (name + ".stl");
    write_file(stl, binary_stl(bent_bar(b.r_bend, b.r_bar, b.sweep_deg, b.n, b.m)));
    const auto r = run_cli("plan '" + stl.string() + "' --layers tilted --strategy single --no-html -o '" + dir.path().string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = read_json(dir / "report.json");
    EXPECT_TRUE(report["support_free"].get<bool>()) << report["unsupported_area_mm2"];
    const auto plan = read_json(dir / "plan.json");
    EXPECT_EQ(plan["regions"][0]["layers"]["strategy"], "tilted");
    check_readback(dir.path(), name);
    const Thickness t = thickness(deposits(slurp(dir / (name + ".ngc"))));
    EXPECT_GT(t.measured, 1000u);
    EXPECT_GE(t.least, proc.value().layer_min_mm - kSlackMm);
    EXPECT_LE(t.most, proc.value().layer_max_mm + kSlackMm);
    EXPECT_LT(t.largest_spread_mm, kSlackMm);  // each layer lies on a plane
    EXPECT_GT(t.largest_turn_deg, 0.2);         // and the planes turn
    expect_rs274_reads(dir.path(), dir / (name + ".ngc"));
  }
}

// On the B/C table the same layers plan: the machine's own read-back (report.json) finds no
// collision, every bead grounded, the program on the plan and inside the limits; rs274 accepts it.
TEST(PlanLayers, TiltedLayersPlanOnTheBCMachineToo) {
  TempDir dir;
  const auto stl = dir / "bar.stl";
  write_file(stl, binary_stl(bent_bar(60, 6, 70, 40, 24)));
  const std::filesystem::path bc = std::filesystem::path(POLYAXIS_PARTS_DIR).parent_path() / "machines" / "ded5_bc.json";
  const auto r = run_cli("plan '" + stl.string() + "' --layers tilted --strategy single --machine '" + bc.string() + "' --no-html -o '" +
                         dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_json(dir / "report.json");
  EXPECT_TRUE(report["support_free"].get<bool>());
  EXPECT_EQ(report["collisions"].get<int>(), 0);
  EXPECT_EQ(report["limit_violations"].get<int>(), 0);
  EXPECT_LE(report["max_tip_deviation_mm"].get<double>(), 0.01);
  EXPECT_EQ(report["build_check"]["ungrounded_samples"].get<int>(), 0);
  EXPECT_EQ(report["build_check"]["head_collisions"].get<int>(), 0);
  expect_rs274_reads(dir.path(), dir / "bar.ngc");
}

TEST(PlanLayers, AutoTakesTiltedLayersWhereThePlanarOnesOverhang) {
  TempDir dir;
  const auto stl = dir / "bar.stl";
  write_file(stl, binary_stl(bent_bar(60, 6, 70, 40, 24)));
  const auto r = run_cli("plan '" + stl.string() + "' --strategy single --no-html -o '" + dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto region = read_json(dir / "plan.json")["regions"][0];
  EXPECT_EQ(region["layers"]["strategy"], "tilted");
  EXPECT_EQ(region["layers"]["rule"], "layers.tilted");
  EXPECT_NE(region["layers"]["why"].get<std::string>().find("on planar"), std::string::npos);
  EXPECT_TRUE(read_json(dir / "report.json")["support_free"].get<bool>());
  check_readback(dir.path(), "bar");
  // `explain` names the rule and its parameters from the rule base.
  const auto why = run_cli("explain '" + (dir / "plan.json").string() + "' --region 0");
  ASSERT_EQ(why.exit_code, 0) << why.err;
  EXPECT_NE(why.out.find("tilted layers by \"layers.tilted\""), std::string::npos) << why.out;
  EXPECT_NE(why.out.find("voldiff = 0.05"), std::string::npos) << why.out;
  // Planar layers along the same direction overhang (the reason auto turned them).
  const auto planar = run_cli("plan '" + stl.string() + "' --strategy single --layers planar --no-html -o '" + (dir / "p").string() + "'");
  ASSERT_EQ(planar.exit_code, 0) << planar.err;
  EXPECT_FALSE(read_json(dir / "p" / "report.json")["support_free"].get<bool>());
}

TEST(PlanLayers, AutoKeepsPlanarLayersWhereTheyLeaveNoOverhang) {
  TempDir dir;
  const auto stl = dir / "box.stl";
  write_file(stl, binary_stl(box({0, 0, 0}, {20, 14, 9})));
  const auto r = run_cli("plan '" + stl.string() + "' --no-html -o '" + dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto region = read_json(dir / "plan.json")["regions"][0];
  EXPECT_EQ(region["layers"]["strategy"], "planar");
  EXPECT_EQ(region["layers"]["why"], "planar layers leave no overhang");
}

// Bent through 110°, the bar's far end faces 20° below the horizontal: tilted layers there would
// bring the head's cylinder into the plate between layers. Asked for, they are refused (exit 4,
// naming the place); under auto, planar layers are taken instead, with the reason.
TEST(PlanLayers, AutoFallsBackToPlanarWhereTheTiltedHeadWouldStrikeThePlate) {
  TempDir dir;
  const auto stl = dir / "bar.stl";
  // A bar bent through 170°: its end comes back down towards the plate, and along the tilted layers
  // there no torch axis within 60° of the layer's normal keeps the head off the plate and the table.
  write_file(stl, binary_stl(bent_bar(40, 8, 170, 48, 16)));
  const auto tilted = run_cli("plan '" + stl.string() + "' --strategy single --layers tilted --no-html -o '" + (dir / "t").string() + "'");
  EXPECT_EQ(tilted.exit_code, 5) << tilted.err;
  EXPECT_NE(tilted.err.find("clear of the plate and the table"), std::string::npos) << tilted.err;
  // One direction as given (auto would turn the bar over), the layers auto.
  const auto r = run_cli("plan '" + stl.string() + "' --strategy single --no-html -o '" + dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("planar layers were chosen because"), std::string::npos) << r.err;
  for (const auto& region : read_json(dir / "plan.json")["regions"]) {
    EXPECT_EQ(region["layers"]["strategy"], "planar");
    EXPECT_EQ(region["layers"]["rule"], "layers.planar");
  }
  check_readback(dir.path(), "bar");
  // Bent through 110°, the tilted layers plan and read back clean (the plate under the bar's foot,
  // the head clear of it past its edge).
  TempDir own;
  const auto stl_own = own / "bar.stl";
  write_file(stl_own, binary_stl(bent_bar(40, 8, 110, 48, 16)));
  const auto on_default = run_cli("plan '" + stl_own.string() + "' --strategy single --layers tilted --no-html -o '" + own.path().string() + "'");
  ASSERT_EQ(on_default.exit_code, 0) << on_default.err;
  EXPECT_EQ(read_json(own / "report.json")["collisions"].get<int>(), 0);
  check_readback(own.path(), "bar");
}

TEST(PlanLayers, TiltedLayersNeedRotaryAxesAndTheTorchTurning) {
  TempDir dir;
  const auto stl = dir / "bar.stl";
  write_file(stl, binary_stl(bent_bar(60, 6, 70, 40, 24)));
  const auto r = run_cli("plan '" + stl.string() + "' --layers tilted --no-tilt --no-html -o '" + dir.path().string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--no-tilt"), std::string::npos) << r.err;
  const std::filesystem::path gantry = std::filesystem::path(POLYAXIS_PARTS_DIR).parent_path() / "machines" / "gantry3.json";
  const auto g = run_cli("plan '" + stl.string() + "' --layers tilted --machine '" + gantry.string() + "' --no-html -o '" + dir.path().string() + "'");
  EXPECT_EQ(g.exit_code, 2) << g.err;
  EXPECT_NE(g.err.find("no rotary axes"), std::string::npos) << g.err;
}

}  // namespace
}  // namespace polyaxis::test

namespace polyaxis::test {
namespace {

// `polyaxis slice --tilted`: the layers alone, with each one's thickness range in layers.json.
TEST(SliceTilted, WritesTiltedLayersWithTheirThicknessRange) {
  TempDir dir;
  const auto stl = dir / "bar.stl";
  write_file(stl, binary_stl(bent_bar(45, 7, 80, 36, 16)));
  const auto r = run_cli("slice '" + stl.string() + "' --tilted --layer 0.6 --min 0.3 --max 0.7 --adaptive voldiff=0.05,overhang=30 -o '" +
                         dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("tilted layers"), std::string::npos) << r.out;
  const auto layers = read_json(dir / "layers.json");
  EXPECT_EQ(layers["summary"]["mode"], "tilted");
  double least = INFINITY, most = 0.0, turn = 0.0;
  core::Vec3 previous{0, 0, 1};
  for (const auto& l : layers["layers"]) {
    least = std::min(least, l["thickness_range_mm"][0].get<double>()), most = std::max(most, l["thickness_range_mm"][1].get<double>());
    const core::Vec3 n{l["normal"][0].get<double>(), l["normal"][1].get<double>(), l["normal"][2].get<double>()};
    turn = std::max(turn, std::acos(std::clamp(core::dot(n, previous), -1.0, 1.0)) * 180.0 / M_PI);
    previous = n;
  }
  EXPECT_GE(least, 0.3 - 1e-6);
  EXPECT_LE(most, 0.7 + 1e-6);
  EXPECT_GT(turn, 0.2);
  // The planar-only limits are refused with --tilted.
  const auto bad = run_cli("slice '" + stl.string() + "' --tilted --adaptive cusp=0.1 -o '" + dir.path().string() + "'");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("planar layers"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace polyaxis::test
