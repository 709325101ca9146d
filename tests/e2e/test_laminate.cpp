// `polyaxis laminate` end to end, judged from its files only: lamination.json against the stock
// and Hayasi's claim, the nesting by exact ring distances, every sheet program through rs274 and,
// read back through the machine's forward kinematics, the jet kept out of the part (half a kerf
// from its own sections) and on the edge lamination.json plans (its samples' cut lines).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "polyaxis/io/read_part.h"
#include "polyaxis/lamination/waterjet.h"
#include "polyaxis/machine/kinematics.h"
#include "polyaxis/machine/machine.h"
#include "support/cli.h"
#include "support/meshes.h"
#include "support/plan_checks.h"
#include "support/waterjet_replay.h"

namespace polyaxis::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Laminated {
  nlohmann::json doc;
  std::size_t jet_samples = 0;
  double worst_gouge = -INFINITY, worst_away = -INFINITY;
};

// Runs laminate on PART with ARGS and checks everything its files say. The machine and process are
// the built-in ones (examples/machines/awj5_head_ac.json, examples/processes/awj_steel.json).
Laminated laminate_and_check(const std::filesystem::path& part, const std::string& args, const std::string& name) {
  Laminated out;
  TempDir dir;
  const auto run = run_cli(fmt::format("-q laminate '{}' {} -o '{}'", part.string(), args, dir.path().string()));
  EXPECT_EQ(run.exit_code, 0) << name << ": " << run.err;
  if (run.exit_code != 0) return out;
  out.doc = read_json(dir / "lamination.json");
  const auto& doc = out.doc;
  const auto machine = machine::parse_machine(lamination::default_waterjet_machine_json(), "m").value();
  const auto process = lamination::parse_waterjet_process(lamination::default_waterjet_process_json(), "p").value();
  auto read = io::read_part(part.string());
  EXPECT_TRUE(read.ok());
  const io::RawMesh& raw = read.value().mesh;
  mesh::Mesh m;
  m.vertices = raw.points;
  m.triangles = raw.triangles;
  core::Box3 box;
  for (const auto& p : raw.points) box.add(p);

  // Layers: from the stock, stacked from the part's bottom over its top.
  std::vector<double> stock;
  for (const auto& t : doc["stock_mm"]) stock.push_back(t.get<double>());
  double z = box.min.z;
  for (const auto& l : doc["layers"]) {
    EXPECT_NE(std::find(stock.begin(), stock.end(), l["thickness_mm"].get<double>()), stock.end()) << name;
    EXPECT_NEAR(l["z_bottom_mm"].get<double>(), z, 1e-6) << name;
    z += l["thickness_mm"].get<double>();
  }
  EXPECT_GE(z, box.max.z - 1e-6) << name;
  EXPECT_LT(doc["sloped_deviation_mm3"].get<double>(), doc["stepped_deviation_mm3"].get<double>()) << name;

  // Nesting: on each sheet the reference outlines keep the margin from each other and the edge.
  const double margin = process.margin_mm;
  for (const auto& sheet : doc["sheets"]) {
    const double w = sheet["size_mm"][0].get<double>(), h = sheet["size_mm"][1].get<double>();
    std::vector<std::vector<P2>> rings;
    for (const auto& piece : sheet["pieces"]) {
      std::vector<P2> ring;
      for (const auto& p : piece["outer"]) ring.push_back({p[0].get<double>(), p[1].get<double>()});
      for (const auto& p : ring) EXPECT_GE(std::min({p.x, p.y, w - p.x, h - p.y}), margin - 1e-3) << name;
      rings.push_back(std::move(ring));
    }
    for (std::size_t i = 0; i < rings.size(); ++i) {
      for (std::size_t j = i + 1; j < rings.size(); ++j) EXPECT_GE(ring_distance(rings[i], rings[j]), margin - 1e-3) << name << " sheet " << sheet["index"];
    }
    EXPECT_GT(sheet["utilisation"].get<double>(), 0.0);
  }

  // Every program: rs274 reads it, and through FK the jet stays out of the part and on its edge.
  std::map<double, std::vector<std::array<P2, 2>>> sections;
  for (const auto& sheet : doc["sheets"]) {
    const auto ngc = dir / sheet["program"].get<std::string>();
    EXPECT_TRUE(std::filesystem::exists(ngc)) << ngc;
    EXPECT_TRUE(std::filesystem::exists(dir / fmt::format("sheet_{}.svg", sheet["index"].get<int>())));
    expect_rs274_reads(dir.path(), ngc);
    std::map<std::pair<int, int>, nlohmann::json> placements;
    std::map<std::pair<int, int>, std::vector<std::array<core::Vec3, 2>>> planned;  // the jet's planned tips, as segments
    for (const auto& piece : sheet["pieces"]) {
      const std::pair<int, int> key{piece["layer"].get<int>(), piece["piece"].get<int>()};
      placements[key] = piece["placement"];
      const auto& layer = doc["layers"][static_cast<std::size_t>(key.first)];
      const double t = layer["thickness_mm"].get<double>(), z_top = layer["z_bottom_mm"].get<double>() + t, z_ref = layer["z_ref_mm"].get<double>();
      const double rot = piece["placement"]["rotation_deg"].get<double>() * kPi / 180.0;
      for (const auto& loop : layer["pieces"][static_cast<std::size_t>(key.second)]["loops"]) {
        const auto& samples = loop["samples"];
        // The loop as docs/laminate.md orders it: from sample 0, round to sample 0 once per pass,
        // each pass on its own cut line.
        auto tip = [&](std::size_t i, int k) {
          const auto& smp = samples[i];
          const auto& cuts = smp[5];
          const auto& cut = cuts[std::min<std::size_t>(static_cast<std::size_t>(k), cuts.size() - 1)];
          const double slope = cut[1].get<double>();
          const double r = cut[0].get<double>() + slope * (z_top - z_ref) + 0.5 * process.kerf_mm * std::sqrt(1.0 + slope * slope);
          const double x = smp[0].get<double>() + smp[2].get<double>() * r, y = smp[1].get<double>() + smp[3].get<double>() * r;
          return core::Vec3{std::cos(rot) * x - std::sin(rot) * y + piece["placement"]["dx_mm"].get<double>() + sheet["origin_mm"][0].get<double>(),
                            std::sin(rot) * x + std::cos(rot) * y + piece["placement"]["dy_mm"].get<double>() + sheet["origin_mm"][1].get<double>(), t};
        };
        core::Vec3 last = tip(0, 0);
        for (int k = 0; k < loop["passes"].get<int>(); ++k) {
          for (std::size_t i = 1; i <= samples.size(); ++i) {
            const core::Vec3 next = tip(i % samples.size(), k);
            planned[key].push_back({last, next});
            last = next;
          }
        }
      }
    }
    const auto blocks = read_program(slurp(ngc), process.jet_on, process.jet_off);
    for (std::size_t b = 1; b < blocks.size(); ++b) {
      if (!blocks[b].jet || !blocks[b].feed) continue;
      const auto& layer = doc["layers"][static_cast<std::size_t>(blocks[b].layer)];
      const double t = layer["thickness_mm"].get<double>(), z0 = layer["z_bottom_mm"].get<double>();
      const auto& pl = placements.at({blocks[b].layer, blocks[b].piece});
      const double rot = pl["rotation_deg"].get<double>() * kPi / 180.0, dx = pl["dx_mm"].get<double>(), dy = pl["dy_mm"].get<double>();
      const bool on_edge = blocks[b].phase.starts_with("pass");
      for (int k = 1; k <= 3; ++k) {
        const double s = k / 3.0;
        const auto& a = blocks[b - 1].pose;
        const auto& e = blocks[b].pose;
        machine::MachinePose q{a.x_mm + s * (e.x_mm - a.x_mm), a.y_mm + s * (e.y_mm - a.y_mm), a.z_mm + s * (e.z_mm - a.z_mm),
                               a.a_or_b_deg + s * (e.a_or_b_deg - a.a_or_b_deg), a.c_deg + s * (e.c_deg - a.c_deg)};
        const auto tool = machine::forward(machine, q);
        if (k == 3 && on_edge) {  // the block's end: on the edge lamination.json plans
          double off = INFINITY;
          for (const auto& [p0, p1] : planned.at({blocks[b].layer, blocks[b].piece})) {
            const core::Vec3 u = p1 - p0;
            const double l2 = core::dot(u, u);
            const double f = l2 > 0 ? std::clamp(core::dot(tool.tip_part_mm - p0, u) / l2, 0.0, 1.0) : 0.0;
            off = std::min(off, core::norm(tool.tip_part_mm - p0 - u * f));
          }
          out.worst_away = std::max(out.worst_away, off);
        }
        for (int j = 0; j <= 6; ++j) {
          const double depth = std::clamp(t * j / 6.0, 1e-3, t - 1e-3);
          const core::Vec3 on = tool.tip_part_mm - tool.tool_axis_part * (depth / tool.tool_axis_part.z);
          const double sx = on.x - sheet["origin_mm"][0].get<double>() - dx, sy = on.y - sheet["origin_mm"][1].get<double>() - dy;
          const P2 p{std::cos(rot) * sx + std::sin(rot) * sy, -std::sin(rot) * sx + std::cos(rot) * sy};
          // Off the planes of the mesh's vertices (a section through a vertex is degenerate).
          const double h = z0 + on.z + 1.234567e-6;
          if (h >= box.max.z) continue;  // above the part's top (a last layer standing out)
          auto& segs = sections[h];
          if (segs.empty()) segs = section_segments(m, h);
          const double out_by = outside_by(p, segs);
          out.worst_gouge = std::max(out.worst_gouge, 0.5 * process.kerf_mm - out_by);
          ++out.jet_samples;
        }
      }
    }
  }
  std::printf("%s: %zu layers on %zu sheets, sloped %.1f vs stepped %.1f mm3; %zu jet samples, worst gouge %.4f mm, farthest from the planned edge %.4f mm\n",
              name.c_str(), doc["layers"].size(), doc["sheets"].size(), doc["sloped_deviation_mm3"].get<double>(), doc["stepped_deviation_mm3"].get<double>(),
              out.jet_samples, out.worst_gouge, out.worst_away);
  EXPECT_GT(out.jet_samples, 0u) << name;
  EXPECT_LE(out.worst_gouge, 0.02) << name << ": the jet enters the part";
  EXPECT_LE(out.worst_away, 0.011) << name << ": the jet leaves the edge lamination.json plans (the post's chordal tolerance)";
  return out;
}

std::filesystem::path write_part(const TempDir& dir, const std::string& name, const io::RawMesh& mesh) {
  const auto path = dir / (name + ".stl");
  write_file(path, binary_stl(mesh));
  return path;
}

std::vector<std::array<double, 2>> profile(const std::function<double(double)>& r, double h, int steps) {
  std::vector<std::array<double, 2>> out;
  for (int k = 0; k <= steps; ++k) out.push_back({r(h * k / steps), h * k / steps});
  return out;
}

TEST(Laminate, DomeSphereWithTheDefaults) {
  const auto r = laminate_and_check(std::filesystem::path(POLYAXIS_PARTS_DIR) / "dome_sphere.stl", "--sheets 1,2,3,6", "dome_sphere");
  ASSERT_FALSE(r.doc.is_null());
  std::uint32_t convex = 0, concave = 0;
  for (const auto& l : r.doc["layers"]) convex += l["edges"]["convex"].get<std::uint32_t>(), concave += l["edges"]["concave"].get<std::uint32_t>();
  EXPECT_GT(convex, 0u);   // the sphere's flanks: several cuts per thick layer
  EXPECT_GT(concave, 0u);  // the dish: one cut
  EXPECT_LT(3.0 * r.doc["sloped_deviation_mm3"].get<double>(), r.doc["stepped_deviation_mm3"].get<double>());
}

TEST(Laminate, PartsOfOurOwn) {
  TempDir dir;
  // A vase: convex belly over a concave waist, with a bore (every kind of edge, and a hole).
  const auto vase = write_part(dir, "vase", revolve(profile([](double z) { return 14.0 + 6.0 * std::sin(z / 40.0 * 2.0 * kPi); }, 40.0, 64), 96, 5.0));
  laminate_and_check(vase, "--sheets 1.5,3,5 --sheet-size 200x150", "vase");
  // A thin neck: two discs joined by a 3 mm waist, on a stock of two sheets.
  const auto neck = write_part(dir, "neck", revolve(profile([](double z) { const double s = (z - 15.0) / 15.0; return 3.0 + 17.0 * s * s; }, 30.0, 48), 80));
  laminate_and_check(neck, "--sheets 2,4 --area-deviation 0.2", "neck");
  // A cone leaning 40° in, coarsely tessellated (24 sides), 25 mm tall to a 4 mm top.
  const auto cone = write_part(dir, "cone", frustum(25.0, 25.0 - 25.0 * std::tan(40.0 * kPi / 180.0), 25.0, 24));
  laminate_and_check(cone, "--sheets 3,6", "cone");
}

TEST(Laminate, ShippedWaterjetFilesAreTheDefaults) {
  // The files in examples/ spell out the embedded defaults key for key.
  const std::filesystem::path examples(POLYAXIS_EXAMPLES_DIR);
  EXPECT_EQ(nlohmann::json::parse(slurp(examples / "machines" / "awj5_head_ac.json")),
            nlohmann::json::parse(std::string(lamination::default_waterjet_machine_json())));
  EXPECT_EQ(nlohmann::json::parse(slurp(examples / "processes" / "awj_steel.json")),
            nlohmann::json::parse(std::string(lamination::default_waterjet_process_json())));
  EXPECT_TRUE(lamination::parse_waterjet_process(slurp(examples / "processes" / "awj_steel.json"), "awj_steel.json").ok());
  EXPECT_TRUE(machine::parse_machine(slurp(examples / "machines" / "awj5_head_ac.json"), "awj5_head_ac.json").ok());
}

TEST(Laminate, BadInputGetsItsExitCode) {
  TempDir dir;
  const std::string dome = (std::filesystem::path(POLYAXIS_PARTS_DIR) / "dome_sphere.stl").string();
  auto code = [&](const std::string& args) { return run_cli("-q laminate " + args + " -o '" + (dir / "out").string() + "'").exit_code; };
  EXPECT_EQ(code("'" + dome + "'"), 2);                         // --sheets is required
  EXPECT_EQ(code("'" + dome + "' --sheets 0"), 2);
  EXPECT_EQ(code("'" + dome + "' --sheets 1,x"), 2);
  EXPECT_EQ(code("'" + dome + "' --sheets 2 --sheet-size 300"), 2);
  EXPECT_EQ(code("'" + dome + "' --sheets 2 --sheet-size 50x50"), 4);  // the Ø80 disc fits no sheet
  EXPECT_EQ(code("'" + (dir / "missing.stl").string() + "' --sheets 2"), 3);
  EXPECT_EQ(code("'" + dome + "' --sheets 2 --machine '" + std::string(POLYAXIS_EXAMPLES_DIR) + "/machines/ded5_ac.json'"), 2);  // not head-head
  EXPECT_EQ(code("'" + dome + "' --sheets 2 --set process.kerf_mm=-1"), 2);
  EXPECT_EQ(code("'" + dome + "' --sheets 2 --set process.jet_on=M2"), 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "lamination.json"));  // nothing written by a failed run
}

TEST(Laminate, SteeperThanTheMachinesJetIsReported) {
  TempDir dir;
  const std::string dome = (std::filesystem::path(POLYAXIS_PARTS_DIR) / "dome_sphere.stl").string();
  const auto run = run_cli("-q laminate '" + dome + "' --sheets 1,2,3,6 --set machine.limits.a.min=-30 --set machine.limits.a.max=30 -o '" + (dir / "o").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("steeper than the jet's 30"), std::string::npos) << run.err;
  const auto doc = read_json(dir / "o" / "lamination.json");
  EXPECT_EQ(doc["max_jet_angle_deg"].get<double>(), 30.0);
  std::uint32_t limited = 0;
  for (const auto& l : doc["layers"]) limited += l["edges"]["at_jet_limit"].get<std::uint32_t>();
  EXPECT_GT(limited, 0u);
}

}  // namespace
}  // namespace polyaxis::test
