#include <gtest/gtest.h>

#include "polyaxis/io/stl.h"
#include "support/meshes.h"

namespace polyaxis::io {
namespace {

TEST(Stl, BinaryCubeSharesIdenticalPoints) {
  const std::string bytes = test::binary_stl(test::soup(test::cube()));
  auto r = read_stl(bytes, "cube.stl");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().format, Format::kStlBinary);
  EXPECT_EQ(r.value().mesh.triangles.size(), 12u);
  EXPECT_EQ(r.value().mesh.points.size(), 8u);
  EXPECT_TRUE(r.value().warnings.empty());
}

TEST(Stl, AsciiCube) {
  auto r = read_stl(test::ascii_stl(test::cube()), "cube.stl");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().format, Format::kStlAscii);
  EXPECT_EQ(r.value().mesh.triangles.size(), 12u);
  EXPECT_EQ(r.value().mesh.points.size(), 8u);
}

TEST(Stl, BinaryWithSolidHeaderIsBinary) {  // F4
  auto r = read_stl(test::binary_stl(test::cube(), "solid cube exported by a CAD"), "cube.stl");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().format, Format::kStlBinary);
}

TEST(Stl, EveryTruncatedPrefixIsAnErrorNeverACrash) {
  const std::string bytes = test::binary_stl(test::cube());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    auto r = read_stl(std::string_view(bytes).substr(0, n), "cut.stl");
    if (n >= 84 && (n - 84) % 50 == 0 && n > 84) {
      EXPECT_TRUE(r.ok()) << n;  // a whole number of records: header count mismatch, trust size
    } else {
      ASSERT_FALSE(r.ok()) << n;
      EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    }
  }
}

TEST(Stl, AsciiCutMidFacetNamesTheLine) {  // F5
  std::string text = test::ascii_stl(test::cube());
  text.resize(text.size() / 2);
  auto r = read_stl(text, "cut.stl");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("line"), std::string::npos) << r.error().message;
}

TEST(Stl, NegativeZeroIsZero) {  // T9
  io::RawMesh m = test::cube();
  m.points.push_back({-0.0, 0.0, -0.0});
  m.triangles[0][0] = 8;  // the same corner as point 0, written as -0
  auto r = read_stl(test::binary_stl(m), "z.stl");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().mesh.points.size(), 8u);
}

}  // namespace
}  // namespace polyaxis::io
