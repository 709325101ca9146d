#include <gtest/gtest.h>

#include "polyaxis/io/obj.h"

namespace polyaxis::io {
namespace {

const char* kCubeQuads =
    "# cube as quads\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vn 0 0 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(Obj, QuadsAreTriangulated) {
  auto r = read_obj(kCubeQuads, "cube.obj");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().mesh.points.size(), 8u);
  EXPECT_EQ(r.value().mesh.triangles.size(), 12u);
}

TEST(Obj, NegativeIndicesResolve) {
  auto r = read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3/1 -2/2/2 -1//3\n", "t.obj");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().mesh.triangles[0], (Triangle{0, 1, 2}));
}

TEST(Obj, ConcaveNgonStaysInside) {
  // An L-shaped hexagon: a fan from corner 0 would leave the outline.
  auto r = read_obj("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 4 5 6 1 2 3\n", "l.obj");
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.value().mesh.triangles.size(), 4u);
  double area = 0;
  for (auto t : r.value().mesh.triangles) {
    const auto& p = r.value().mesh.points;
    const auto c = core::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    EXPECT_GT(c.z, 0.0);  // every triangle keeps the polygon's orientation
    area += c.z / 2;
  }
  EXPECT_DOUBLE_EQ(area, 3.0);
}

TEST(Obj, BadIndicesNameTheLine) {  // F14
  for (const char* text : {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "f 1 2 3\n",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n"}) {
    auto r = read_obj(text, "bad.obj");
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_EQ(r.error().code, core::ErrorCode::kInvalidInput);
    EXPECT_NE(r.error().message.find("line"), std::string::npos) << r.error().message;
  }
}

}  // namespace
}  // namespace polyaxis::io
