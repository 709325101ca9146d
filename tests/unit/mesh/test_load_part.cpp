// mesh::load_part: the one chain of reading, scaling and repair the CLI and the bindings share; a
// mesh from memory is checked as a reader checks a file.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "polyaxis/mesh/load_part.h"

namespace polyaxis::mesh {
namespace {

io::RawMesh tetrahedron(double size) {
  return io::RawMesh{{{0, 0, 0}, {size, 0, 0}, {0, size, 0}, {0, 0, size}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

TEST(LoadPart, AMeshFromMemoryIsScaledAndRepaired) {
  LoadOptions options;
  options.scale = 2.0;
  auto part = load_part(tetrahedron(3.0), options, "<arrays>");
  ASSERT_TRUE(part) << part.error().message;
  double volume = 0.0;
  for (const auto& s : part.value().repaired.shells) volume += s.volume_mm3;
  EXPECT_NEAR(volume, 36.0, 1e-9);  // (6 mm)^3 / 6
  EXPECT_TRUE(part.value().repaired.watertight);
}

TEST(LoadPart, AMeshFromMemoryIsCheckedAsAFileIs) {
  io::RawMesh bad_index = tetrahedron(1.0);
  bad_index.triangles[2][1] = 9;
  auto a = load_part(bad_index, {}, "<arrays>");
  ASSERT_FALSE(a);
  EXPECT_EQ(a.error().code, core::ErrorCode::kInvalidInput);
  EXPECT_NE(a.error().message.find("triangle 2 names vertex 9 of 4"), std::string::npos) << a.error().message;

  io::RawMesh not_finite = tetrahedron(1.0);
  not_finite.points[3].y = std::numeric_limits<double>::quiet_NaN();
  auto b = load_part(not_finite, {}, "<arrays>");
  ASSERT_FALSE(b);
  EXPECT_EQ(b.error().code, core::ErrorCode::kInvalidInput);
  EXPECT_NE(b.error().message.find("<arrays>: vertex 3 is not finite"), std::string::npos) << b.error().message;

  LoadOptions zero_scale;
  zero_scale.scale = 0.0;
  auto c = load_part(tetrahedron(1.0), zero_scale, "<arrays>");
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, core::ErrorCode::kUsage);
}

TEST(LoadPart, AFileThatIsNotThereNamesItself) {
  LoadOptions options;
  options.path = "/nonexistent/part.stl";
  auto part = load_part(options);
  ASSERT_FALSE(part);
  EXPECT_EQ(part.error().code, core::ErrorCode::kInvalidInput);
  EXPECT_NE(part.error().message.find("/nonexistent/part.stl"), std::string::npos);
}

}  // namespace
}  // namespace polyaxis::mesh
