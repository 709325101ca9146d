// Building onto a prebuilt part (issue 13, item 3): `plan --substrate MESH` and `plan --prebuilt ID`,
// judged from the G-code alone. The program is read back through forward kinematics with the
// substrate placed as plan.json says (support/plan_checks.h): every bead rests on the substrate or
// on earlier deposit, the head keeps out of the substrate, and rs274 accepts the program. Without
// the substrate in that reading the first beads hang in the air: the plan really is laid onto it.
// A head that cannot keep clear of the substrate is refused, naming it.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "polyaxis/io/read_part.h"
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/repair.h"
#include "support/cli.h"
#include "support/mesh_union.h"
#include "support/meshes.h"
#include "support/plan_checks.h"

namespace polyaxis::test {
namespace {

using core::Vec3;

struct OnSubstrate {
  std::string name;
  RawMesh part, substrate;
  std::string extra;  // more options
};

// The lowest deposit point of the program in DIR read back, table frame.
double lowest_deposit_z(const std::filesystem::path& dir, const std::string& name) {
  double low = INFINITY;
  for (const Tip& t : deposit_tips(dir, name)) low = std::min(low, t.tip.z);
  return low;
}

// Every bead of the program in DIR over the substrate ON_TABLE is at least the process's least
// thickness thick: from the substrate's surface along the layer's normal under its tip to its
// layer's top (the tip on the layer's mid-plane, half its thickness under the top).
void expect_thick_enough_over(const std::filesystem::path& dir, const std::string& name, const RawMesh& on_table) {
  auto process = process::parse_process(process::default_process_json(), "default");
  const auto plan = read_json(dir / "plan.json");
  const double least = process.value().layer_min_mm;
  std::size_t over = 0, thin = 0;
  double thinnest = INFINITY;
  for (const Tip& t : deposit_tips(dir, name)) {
    const auto& layer = plan["layers"][static_cast<std::size_t>(t.layer)];
    const Vec3 n = core::normalized({layer["normal"][0].get<double>(), layer["normal"][1].get<double>(), layer["normal"][2].get<double>()});
    const double depth = depth_under(on_table, t.tip, n), half = 0.5 * layer["thickness_mm"].get<double>();
    if (!(depth < 2.0 * process.value().layer_max_mm)) continue;  // farther: on earlier deposit
    ++over;
    thinnest = std::min(thinnest, depth + half);
    if (depth + half < least - 1e-3) ++thin;
  }
  EXPECT_GT(over, 0u);
  EXPECT_EQ(thin, 0u) << "thinnest " << thinnest << " mm over the substrate, least " << least;
}

TEST(PlanSubstrate, DepositLaidOntoASubstrateReadsBackGroundedAndClearOfIt) {
  const std::vector<OnSubstrate> cases = {
      {"boss_on_block", cylinder({0, 0, 5}, {0, 0, 1}, 8, 20, 48), box({-20, -20, 0}, {20, 20, 10}), ""},
      {"thin_boss_on_slab", cylinder({3, -4, 2}, {0, 0, 1}, 4, 9, 24), box({-25, -15, 0}, {25, 15, 4}), ""},
      // Hybrid repair: the whole block given, the worn stump as the substrate.
      {"repair_block", box({-15, -15, 0}, {15, 15, 30}), box({-15, -15, 0}, {15, 15, 18}), ""},
      {"repair_low_stump", box({-10, -12, 0}, {10, 12, 16}), box({-10, -12, 0}, {10, 12, 5}), ""},
      // Features growing from a dome's surface, one of them leaning (the torch tilts over its overhang).
      {"bosses_on_dome", join(cylinder({0, 0, 15}, {0, 0, 1}, 6, 15, 40), cylinder({18, 0, 8}, {0.3, 0, 1}, 5, 14, 40)),
       spherical_cap(40, 20, 96, 24), ""},
      {"boss_on_coarse_dome", cylinder({-10, 5, 10}, {0, 0, 1}, 7, 14, 32), spherical_cap(35, 15, 40, 8), ""},
  };
  for (const OnSubstrate& c : cases) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    const auto part = dir / (c.name + ".stl"), substrate = dir / "substrate.stl";
    write_file(part, binary_stl(c.part));
    write_file(substrate, binary_stl(c.substrate));
    const auto r = run_cli("plan '" + part.string() + "' --substrate '" + substrate.string() + "' --no-html -o '" + dir.path().string() + "'" +
                           c.extra);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto plan = read_json(dir / "plan.json");
    ASSERT_EQ(plan["regions"].size(), 2u);
    EXPECT_TRUE(plan["regions"][0]["prebuilt"].get<bool>());
    EXPECT_FALSE(plan["regions"][1]["prebuilt"].get<bool>());
    for (const auto& l : plan["layers"]) EXPECT_EQ(l["region"].get<int>(), 1);  // the substrate is never deposited
    const RawMesh on_table = placed(c.substrate, plan);
    const ReadBack rb = check_readback(dir.path(), c.name, false, &on_table);
    EXPECT_EQ(rb.ungrounded, 0u) << rb.first_problem;
    expect_rs274_reads(dir.path(), dir / (c.name + ".ngc"));
    // Read back without the substrate, the first beads hang in the air above the plate.
    auto machine = machine::parse_machine(machine::default_machine_json(), "default");
    auto process = process::parse_process(process::default_process_json(), "default");
    const auto report = read_json(dir / "report.json");
    const auto& sub = report["substrate"];
    const Plate plate{sub["x_mm"][0].get<double>(), sub["x_mm"][1].get<double>(), sub["y_mm"][0].get<double>(),
                      sub["y_mm"][1].get<double>(), sub["top_z_mm"].get<double>(), sub["top_z_mm"].get<double>() - 10.0};
    const ReadBack bare = read_back(machine.value(), process.value(), plate, slurp(dir / (c.name + ".ngc")), 1.2, 0.225);
    EXPECT_FALSE(bare.regions_starting_in_air.empty());
    EXPECT_GT(lowest_deposit_z(dir.path(), c.name), 2.0);  // on the substrate, not on the plate
    expect_thick_enough_over(dir.path(), c.name, on_table);
  }
}

// Bosses standing on a dome along its normals, too far off vertical for one direction on planar
// layers: each piece grows along the dome's normal under it (auto takes that), reads back clean and
// stays thick enough over the dome. (On conformal layers one region can build them all: auto layers
// may take that instead; test_plan_conformal.cpp.)
TEST(PlanSubstrate, PiecesGrowAlongTheSubstratesNormalUnderThem) {
  struct Case {
    std::string name;
    double radius, height;
    std::uint32_t n, m;
    std::vector<double> polar_deg;
  };
  const std::vector<Case> cases = {{"three_on_dome", 30, 25, 96, 32, {45, 40, 40}}, {"four_on_flat_dome", 45, 20, 64, 20, {38, 35, 30, 25}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const double zc = c.height - c.radius;
    RawMesh bosses;
    std::vector<Vec3> axes;
    for (std::size_t i = 0; i < c.polar_deg.size(); ++i) {
      const double pol = c.polar_deg[i] * M_PI / 180.0, az = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(c.polar_deg.size());
      const Vec3 n{std::sin(pol) * std::cos(az), std::sin(pol) * std::sin(az), std::cos(pol)};
      bosses = join(bosses, cylinder(Vec3{0, 0, zc} + n * (c.radius - 3.0), n, 4, 14, 40));
      axes.push_back(n);
    }
    const RawMesh dome = spherical_cap(c.radius, c.height, c.n, c.m);
    TempDir dir;
    write_file(dir / (c.name + ".stl"), binary_stl(bosses));
    write_file(dir / "dome.stl", binary_stl(dome));
    const auto r = run_cli("plan '" + (dir / (c.name + ".stl")).string() + "' --substrate '" + (dir / "dome.stl").string() +
                           "' --layers planar --no-html -o '" + dir.path().string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = read_json(dir / "report.json");
    EXPECT_EQ(report["strategy"].get<std::string>(), "decompose");
    EXPECT_TRUE(report["support_free"].get<bool>());
    const auto plan = read_json(dir / "plan.json");
    ASSERT_EQ(plan["regions"].size(), axes.size() + 1);
    // Each boss's region grows along its own axis (the dome's normal under it), placed on the table.
    const auto& rows = plan["placement_rotation"];
    for (std::size_t k = 1; k < plan["regions"].size(); ++k) {
      const auto& d = plan["regions"][k]["build_direction"];
      const Vec3 dir_table{d[0].get<double>(), d[1].get<double>(), d[2].get<double>()};
      double best = -1.0;
      for (const Vec3& a : axes) {
        const Vec3 placed{rows[0][0].get<double>() * a.x + rows[0][1].get<double>() * a.y + rows[0][2].get<double>() * a.z,
                          rows[1][0].get<double>() * a.x + rows[1][1].get<double>() * a.y + rows[1][2].get<double>() * a.z,
                          rows[2][0].get<double>() * a.x + rows[2][1].get<double>() * a.y + rows[2][2].get<double>() * a.z};
        best = std::max(best, core::dot(placed, dir_table));
      }
      EXPECT_GT(best, std::cos(3.0 * M_PI / 180.0)) << "region " << k;
    }
    const RawMesh on_table = placed(dome, plan);
    const ReadBack rb = check_readback(dir.path(), c.name, false, &on_table);
    EXPECT_EQ(rb.ungrounded, 0u) << rb.first_problem;
    expect_thick_enough_over(dir.path(), c.name, on_table);
    expect_rs274_reads(dir.path(), dir / (c.name + ".ngc"));
  }
}

TEST(PlanSubstrate, AHeadThatWouldStrikeTheSubstrateIsRefusedNamingIt) {
  // A boss on the plate beside a tall prebuilt block: the head's 25 mm cylinder reaches over the
  // block wherever the boss is laid, and no tilt turns it away.
  TempDir dir;
  const auto part = dir / "boss.stl", substrate = dir / "tower.stl";
  const RawMesh tower = box({0, -20, 0}, {20, 20, 60});
  write_file(part, binary_stl(cylinder({-6, 0, 0}, {0, 0, 1}, 4, 10, 32)));
  write_file(substrate, binary_stl(tower));
  const std::string args = "plan '" + part.string() + "' --substrate '" + substrate.string() + "' --no-html -o '";
  const auto refused = run_cli(args + (dir / "no").string() + "'");
  EXPECT_EQ(refused.exit_code, 4) << refused.err;
  EXPECT_NE(refused.err.find("prebuilt part"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "no" / "plan.json"));
  const auto kept = run_cli(args + dir.path().string() + "' --allow-collisions");
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  const auto report = read_json(dir / "report.json");
  EXPECT_GT(report["build_check"]["prebuilt_collisions"].get<int>(), 0);
  bool named = false;
  for (const auto& c : report["collision_list"]) named = named || c["body"].get<std::string>() == "prebuilt part";
  EXPECT_TRUE(named);
  // The test's own reading agrees: the head holds the tower.
  const RawMesh on_table = placed(tower, read_json(dir / "plan.json"));
  const ReadBack rb = check_readback(dir.path(), "boss", true, &on_table);
  EXPECT_GT(rb.head_in_prebuilt, 0u);
}

TEST(PlanSubstrate, BadSubstrateOptionsGetUsageErrors) {
  TempDir dir;
  const auto part = dir / "p.stl", substrate = dir / "s.stl";
  write_file(part, binary_stl(box({-5, -5, 0}, {5, 5, 20})));
  write_file(substrate, binary_stl(box({-5, -5, 0}, {5, 5, 8})));
  const std::string base = "plan '" + part.string() + "' --no-html -o '" + dir.path().string() + "' ";
  // One piece growing straight up: decomposed, it is that one region along the substrate's normal.
  ASSERT_EQ(run_cli(base + "--substrate '" + substrate.string() + "' --strategy decompose").exit_code, 0);
  EXPECT_EQ(read_json(dir / "plan.json")["regions"].size(), 2u);
  EXPECT_EQ(run_cli(base + "--substrate '" + substrate.string() + "' --prebuilt 0").exit_code, 2);
  EXPECT_EQ(run_cli(base + "--prebuilt 0 --strategy single").exit_code, 2);
  EXPECT_EQ(run_cli(base + "--substrate '" + (dir / "missing.stl").string() + "'").exit_code, 3);
  // A substrate holding the whole part leaves nothing to build.
  const auto all = run_cli("plan '" + substrate.string() + "' --substrate '" + part.string() + "' --no-html -o '" + dir.path().string() + "'");
  EXPECT_EQ(all.exit_code, 4) << all.err;
  EXPECT_NE(all.err.find("nothing to build"), std::string::npos) << all.err;
}

TEST(PlanSubstrate, PrebuiltRootOfTheDecompositionIsNotDepositedAndGroundsItsChildren) {
  // The reference L-block and an L of other proportions: the root column is prebuilt, the arm is
  // laid onto it along its own direction.
  struct Case {
    std::string name;
    RawMesh part;
  };
  const std::vector<Case> cases = {
      {"l_other", prism_xz({{0, 0}, {18, 0}, {18, 30}, {46, 30}, {46, 44}, {0, 44}}, 14)},
  };
  std::vector<std::pair<std::string, std::filesystem::path>> parts;
  TempDir dir;
  for (const Case& c : cases) {
    write_file(dir / (c.name + ".stl"), binary_stl(c.part));
    parts.push_back({c.name, dir / (c.name + ".stl")});
  }
  parts.push_back({"l_block", std::filesystem::path(POLYAXIS_PARTS_DIR) / "l_block.stl"});
  for (const auto& [name, path] : parts) {
    SCOPED_TRACE(name);
    const auto out = dir / ("out_" + name);
    const auto r = run_cli("plan '" + path.string() + "' --prebuilt 0 --no-html -o '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto plan = read_json(out / "plan.json");
    ASSERT_GE(plan["regions"].size(), 2u);
    for (const auto& region : plan["regions"]) EXPECT_EQ(region["prebuilt"].get<bool>(), region["id"].get<int>() == 0);
    for (const auto& l : plan["layers"]) EXPECT_NE(l["region"].get<int>(), 0);
    // The root where plan.json places it (table frame) is the part the test reads the program against.
    RawMesh root;
    const auto& v = plan["regions"][0]["vertices"];
    for (std::size_t i = 0; i + 2 < v.size(); i += 3) root.points.push_back({v[i].get<double>(), v[i + 1].get<double>(), v[i + 2].get<double>()});
    const auto& t = plan["regions"][0]["triangles"];
    for (std::size_t i = 0; i + 2 < t.size(); i += 3) root.triangles.push_back({t[i].get<std::uint32_t>(), t[i + 1].get<std::uint32_t>(), t[i + 2].get<std::uint32_t>()});
    const ReadBack rb = check_readback(out, name, false, &root);
    EXPECT_EQ(rb.ungrounded, 0u) << rb.first_problem;
    expect_rs274_reads(out, out / (name + ".ngc"));
  }
  const auto bad = run_cli("plan '" + parts.back().second.string() + "' --prebuilt 7 --no-html -o '" + (dir / "bad").string() + "'");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("--prebuilt 7"), std::string::npos) << bad.err;
  const auto child = run_cli("plan '" + parts.back().second.string() + "' --prebuilt 1 --no-html -o '" + (dir / "child").string() + "'");
  EXPECT_EQ(child.exit_code, 2) << child.err;
}

// FRUSTUM with each side quad split along its other diagonal: the same surface, tessellated as
// another program would.
RawMesh other_diagonals(RawMesh frustum) {
  for (io::Triangle& t : frustum.triangles) {
    // The side quads' triangles are (a, b, b+1) and (a, b+1, a+1), a and b even (meshes.h).
    if (t[0] % 2 == 0 && t[1] % 2 == 0 && t[2] == t[1] + 1) {
      t = {t[0], t[1], t[0] + 1};
    } else if (t[0] % 2 == 0 && t[1] % 2 == 1 && t[2] == t[0] + 1 && t[1] != t[0] + 1) {
      t = {t[1] - 1, t[1], t[0] + 1};
    }
  }
  return frustum;
}

// A substrate of two blocks closer than twice the skin: grown, they cross, and the difference
// with that skin took the whole part (exit 4, "nothing to build"); the skin's outer surface is
// taken instead (the two blocks' skins as one), and the boss standing on both is deposited.
TEST(PlanSubstrate, ASubstrateWhoseGrownSkinFoldsIsPlanned) {
  for (const double gap : {0.01, 0.03}) {
    SCOPED_TRACE(gap);
    TempDir dir;
    const RawMesh part = mesh_union(box({0, 0, 0}, {20 + gap, 20, 10}), cylinder({10 + 0.5 * gap, 10, 5}, {0, 0, 1}, 5, 20, 40));
    const RawMesh substrate = join(box({0, 0, 0}, {10, 20, 10}), box({10 + gap, 0, 0}, {20 + gap, 20, 10}));
    write_file(dir / "boss.stl", binary_stl(part));
    write_file(dir / "blocks.stl", binary_stl(substrate));
    const auto r = run_cli("plan '" + (dir / "boss.stl").string() + "' --substrate '" + (dir / "blocks.stl").string() + "' --no-html -o '" +
                           dir.path().string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto plan = read_json(dir / "plan.json");
    double deposited = 0.0;
    for (std::size_t k = 1; k < plan["regions"].size(); ++k) deposited += plan["regions"][k]["volume_mm3"].get<double>();
    EXPECT_GT(deposited, 0.9 * M_PI * 25.0 * 15.0);  // the boss above the blocks
    const RawMesh on_table = placed(substrate, plan);
    check_readback(dir.path(), "boss", false, &on_table);
  }
}

// A substrate cut from the part itself below a plane through the seam of its union (two_branches:
// OpenSCAD left slivers where the 64-sided trunk meets the 48-sided arm), so that its faces lie on
// the part's: grown by the skin it crosses itself along the seam, and the part less the substrate
// as given never finished (16 minutes in CGAL's corefinement before it was stopped). Now the skin's
// outer surface is taken: the plan finishes, deposits only what stands above the cut, onto it.
TEST(PlanSubstrate, ASubstrateCutFromThePartAcrossItsSeamIsPlanned) {
  auto read = io::read_part(std::string(POLYAXIS_PARTS_DIR) + "/two_branches.stl");
  ASSERT_TRUE(read.ok());
  auto repaired = mesh::repair(read.value().mesh);
  ASSERT_TRUE(repaired.ok());
  const mesh::Mesh& part = repaired.value().mesh;
  for (const double z : {35.0, 50.0}) {
    SCOPED_TRACE(z);
    auto cut = mesh::cut_by_plane(part, {0, 0, z}, {0, 0, 1});
    ASSERT_TRUE(cut.ok());
    TempDir dir;
    const RawMesh substrate{cut.value().below.vertices, cut.value().below.triangles};
    write_file(dir / "stump.stl", binary_stl(substrate));
    const auto r = run_cli("plan '" + std::string(POLYAXIS_PARTS_DIR) + "/two_branches.stl' --substrate '" + (dir / "stump.stl").string() +
                           "' --strategy single --layers planar --no-html -o '" + dir.path().string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto plan = read_json(dir / "plan.json");
    ASSERT_EQ(plan["regions"].size(), 2u);
    const double above = mesh::signed_volume(part) - mesh::signed_volume(cut.value().below);
    EXPECT_NEAR(plan["regions"][1]["volume_mm3"].get<double>(), above, 0.01 * above);
    for (const auto& l : plan["layers"]) EXPECT_EQ(l["region"].get<int>(), 1);
    const RawMesh on_table = placed(substrate, plan);
    check_readback(dir.path(), "two_branches", false, &on_table);
    EXPECT_GT(lowest_deposit_z(dir.path(), "two_branches"), z - 1.0);  // on the stump, not on the plate
  }
}

// Fins on a flaring hub (R0 at z = 0 to R1 at H, SIDES sides), FINS of them 3 mm thick from 2 mm
// inside the hub to 14 mm beyond its widest, turned TURN_DEG about Z; the hub given apart as the
// substrate, its sides split along the other diagonals (as when a hub and its impeller are exported
// one by one), standing on a shaft so that the fins clear the plate.
struct FinnedHub {
  std::string name;
  double r0, r1, h;
  std::uint32_t sides, fins;
  double turn_deg = 0.0;
  RawMesh part() const {
    RawMesh out = frustum(r0, r1, h, sides);
    for (std::uint32_t k = 0; k < fins; ++k) {
      const double u = 2.0 * M_PI * (k + 0.5) / fins + turn_deg * M_PI / 180.0;
      const Vec3 radial{std::cos(u), std::sin(u), 0.0}, side{-std::sin(u), std::cos(u), 0.0};
      RawMesh fin = box({r0 - 2.0, -1.5, 2.0}, {r1 + 14.0, 1.5, h - 2.0});
      for (Vec3& p : fin.points) p = radial * p.x + side * p.y + Vec3{0, 0, p.z};
      out = mesh_union(out, fin);
    }
    return out;
  }
  RawMesh substrate() const { return mesh_union(other_diagonals(frustum(r0, r1, h, sides)), cylinder({0, 0, -30}, {0, 0, 1}, 10, 30.5, 32)); }
};

// Plans the fins onto their hub with LAYERS (--strategy decompose) in DIR and checks the plan read
// back: every fin a region of its own along the hub's normal, grounded and clear, rs274 accepts it.
nlohmann::json expect_fins_planned(const TempDir& dir, const FinnedHub& c, const std::string& layers) {
  const RawMesh substrate = c.substrate();
  write_file(dir / (c.name + ".stl"), binary_stl(c.part()));
  write_file(dir / "hub.stl", binary_stl(substrate));
  const auto r = run_cli("plan '" + (dir / (c.name + ".stl")).string() + "' --substrate '" + (dir / "hub.stl").string() +
                         "' --strategy decompose --layers " + layers + " --no-html -o '" + dir.path().string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return {};
  const auto plan = read_json(dir / "plan.json");
  EXPECT_EQ(plan["regions"].size(), c.fins + 1);
  const double slope = std::atan2(c.r1 - c.r0, c.h);
  for (std::size_t k = 1; k < plan["regions"].size(); ++k) {
    const auto& d = plan["regions"][k]["build_direction"];
    // Along the hub's normal: as far below the horizon as the hub flares (placed about Z only).
    EXPECT_NEAR(std::asin(d[2].get<double>()), -slope, 2.0 * M_PI / 180.0) << "region " << k;
    // A whole fin: at least its part outside the hub's widest section, 3 × (h − 4) × 14 mm.
    EXPECT_GT(plan["regions"][k]["volume_mm3"].get<double>(), 3.0 * (c.h - 4.0) * 14.0) << "region " << k;
  }
  const RawMesh on_table = placed(substrate, plan);
  const ReadBack rb = check_readback(dir.path(), c.name, false, &on_table);
  EXPECT_EQ(rb.ungrounded, 0u) << rb.first_problem;
  expect_rs274_reads(dir.path(), dir / (c.name + ".ngc"));
  return plan;
}

// The part less the hub is the fins, each a piece of its own grown along the hub's normal under
// it, not one piece joined by the slivers between the two tessellations.
TEST(PlanSubstrate, FinsOnAHubGivenApartWithOtherDiagonalsAreEachAPiece) {
  for (const FinnedHub& c : {FinnedHub{"four_fins", 16, 24, 24, 48, 4}, FinnedHub{"three_fins", 18, 22, 20, 36, 3}}) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    expect_fins_planned(dir, c, "planar");
  }
}

// The same on conformal layers from the hub, the torch along the hub's normal: read back, no bead
// is laid off the part (a path whose first two points fell together once took the second's
// process-on flag, so the plunge from the approach point deposited 5 mm out in the air and the
// head struck that bead), and each fin's every layer is conformal.
TEST(PlanSubstrate, FinsOnAHubOnConformalLayersReadBackClean) {
  for (const FinnedHub& c : {FinnedHub{"six_fins", 18, 26, 34, 90, 6, 10.0}, FinnedHub{"five_fins", 16, 22, 28, 64, 5, -7.0}}) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    const auto plan = expect_fins_planned(dir, c, "conformal");
    if (plan.is_null()) continue;
    for (std::size_t k = 1; k < plan["regions"].size(); ++k) EXPECT_EQ(plan["regions"][k]["layers"]["strategy"], "conformal") << "region " << k;
  }
}

}  // namespace
}  // namespace polyaxis::test
