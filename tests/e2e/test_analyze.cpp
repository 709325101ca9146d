// `polyaxis analyze` end to end: analysis.json's schema (docs/analyze.md) and the region STLs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "polyaxis/io/read_part.h"
#include "support/cli.h"
#include "support/meshes.h"

namespace polyaxis::test {
namespace {

double volume_of(const io::RawMesh& m) {
  double six = 0.0;
  for (const auto& t : m.triangles) {
    const core::Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
    six += core::dot(a, core::cross(b, c));
  }
  return six / 6.0;
}

TEST(AnalyzeCli, TwoBranchesWritesTheSchemaAndOneStlPerRegion) {
  TempDir dir;
  const std::string part = std::string(POLYAXIS_PARTS_DIR) + "/two_branches.stl";
  const auto r = run_cli("analyze '" + part + "' --json -o '" + dir.path().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(slurp(dir / "analysis.json"));
  EXPECT_EQ(nlohmann::json::parse(r.out), doc);  // --json prints the file
  EXPECT_GT(doc["overhang_area_mm2"].get<double>(), 600.0);
  for (const auto& n : doc["centroidal_axis"]["nodes"]) {
    for (const char* key : {"id", "position", "direction", "area_mm2"}) EXPECT_TRUE(n.contains(key)) << key;
  }
  for (const auto& l : doc["centroidal_axis"]["links"]) {
    for (const char* key : {"from", "to", "break"}) EXPECT_TRUE(l.contains(key)) << key;
  }
  EXPECT_FALSE(doc["skeleton"]["nodes"].empty());
  EXPECT_FALSE(doc["skeleton"]["edges"].empty());
  const auto& regions = doc["regions"];
  ASSERT_GE(regions.size(), 3u);
  double total = 0.0;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const auto& g = regions[i];
    EXPECT_EQ(g["id"].get<std::size_t>(), i);
    EXPECT_EQ(g["parent"].is_null(), i == 0);
    // Support-free but for corners where a region starts on nothing, which the file lists.
    EXPECT_EQ(g["unsupported_area_mm2"].get<double>(), 0.0) << i;
    EXPECT_EQ(g["support_free"].get<bool>(), g["mid_air_starts"].empty()) << i;
    for (const auto& p : g["mid_air_starts"]) EXPECT_EQ(p.size(), 3u) << i;
    // Build order: what a region rests on comes before it, its parent among them.
    for (const auto& below : g["rests_on"]) EXPECT_LT(below.get<std::size_t>(), i);
    if (i > 0) {
      EXPECT_NE(std::find(g["rests_on"].begin(), g["rests_on"].end(), g["parent"]), g["rests_on"].end()) << i;
    }
    auto stl = io::read_part((dir / g["stl"].get<std::string>()).string());
    ASSERT_TRUE(stl.ok()) << g["stl"];
    const double v = volume_of(stl.value().mesh);
    EXPECT_NEAR(v, g["volume_mm3"].get<double>(), 1e-3 * g["volume_mm3"].get<double>()) << i;  // STL floats
    total += v;
  }
  EXPECT_NEAR(total, 14717.2, 0.001 * 14717.2);  // parts/README.md
}

// Bodies put together without a union: an L-block of two overlapping boxes is united and
// decomposed as the L-block is (two regions, 44 000 mm3; the cuts crashed in CGAL on the crossing
// faces before), and inspect gives the union's volume. Two boxes, one of them crossing itself (a corner pushed through the opposite
// face), cannot be united: refused with the reason, exit 4, nothing written.
TEST(AnalyzeCli, OverlappingBodiesAreUnitedAndASurfaceCrossingItselfIsRefused) {
  TempDir dir;
  const auto l = dir / "overlap.stl";
  write_file(l, binary_stl(join(box({0, 0, 0}, {20, 20, 60}), box({5, 0, 40}, {70, 20, 60}))));
  const auto r = run_cli("analyze '" + l.string() + "' -o '" + (dir / "l").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(slurp(dir / "l" / "analysis.json"));
  ASSERT_EQ(doc["regions"].size(), 2u);
  EXPECT_NEAR(doc["regions"][0]["volume_mm3"].get<double>() + doc["regions"][1]["volume_mm3"].get<double>(), 44000.0, 1.0);
  // inspect measures the union too (the shells' sum is 50 000 mm3), and says so.
  const auto i = run_cli("inspect --json '" + l.string() + "'");
  ASSERT_EQ(i.exit_code, 0) << i.err;
  const auto inspected = nlohmann::json::parse(i.out);
  EXPECT_NEAR(inspected["volume_mm3"].get<double>(), 44000.0, 1e-6);
  EXPECT_TRUE(inspected["bodies_united"].get<bool>());
  EXPECT_EQ(inspected["shells"].get<int>(), 2);
  io::RawMesh folded = box({0, 0, 0}, {20, 20, 20});
  folded.points[7] = {-10, 10, 10};  // the corner (20, 20, 20) pushed through the face x = 0
  const auto bad = dir / "folded.stl";
  write_file(bad, binary_stl(join(folded, box({10, 0, 10}, {40, 20, 30}))));
  const auto f = run_cli("analyze '" + bad.string() + "' -o '" + (dir / "f").string() + "'");
  EXPECT_EQ(f.exit_code, 4) << f.err;  // infeasible geometry
  EXPECT_NE(f.err.find("crosses itself"), std::string::npos) << f.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "f" / "analysis.json"));
}

}  // namespace
}  // namespace polyaxis::test
