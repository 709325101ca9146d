// read_3mf: geometry, transforms, components, and every F15 case of RELIABILITY.md. The archives
// are built here in memory with libzip from hand-written model XML, so each case shows exactly
// what the file holds.
#include <gtest/gtest.h>
#include <zip.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/io/three_mf.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;

constexpr const char* kContentTypes =
    R"(<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
 <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
 <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
</Types>)";

constexpr const char* kRels =
    R"(<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
 <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>)";

using Entries = std::vector<std::pair<std::string, std::string>>;

// A zip archive holding ENTRIES (deflated), built in memory.
std::string make_zip(const Entries& entries) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (source == nullptr) throw std::runtime_error("zip_source_buffer_create");
  zip_t* archive = zip_open_from_source(source, ZIP_TRUNCATE, &error);
  if (archive == nullptr) throw std::runtime_error("zip_open_from_source");
  zip_source_keep(source);
  for (const auto& [name, content] : entries) {
    zip_source_t* file = zip_source_buffer(archive, content.data(), content.size(), 0);
    if (file == nullptr || zip_file_add(archive, name.c_str(), file, ZIP_FL_ENC_UTF_8) < 0) {
      throw std::runtime_error("zip_file_add");
    }
  }
  if (zip_close(archive) != 0) throw std::runtime_error("zip_close");
  std::string out;
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_source_open(source) != 0 || zip_source_stat(source, &st) != 0) throw std::runtime_error("zip_source_open");
  out.resize(st.size);
  if (zip_source_read(source, out.data(), out.size()) != static_cast<zip_int64_t>(out.size())) {
    throw std::runtime_error("zip_source_read");
  }
  zip_source_close(source);
  zip_source_free(source);
  return out;
}

std::string model_xml(const std::string& resources, const std::string& build, const char* unit = "millimeter") {
  return std::string(R"(<?xml version="1.0" encoding="UTF-8"?>
<model unit=")") + unit + R"(" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">
 <resources>)" + resources + "</resources>\n <build>" + build + "</build>\n</model>\n";
}

// A 3MF package around MODEL (the 3D/3dmodel.model part).
std::string package(const std::string& model) {
  return make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels}, {"3D/3dmodel.model", model}});
}

// The unit cube [0,1]^3 as mesh object ID, outward-oriented: 8 vertices, 12 triangles.
// EXTRA_TRIANGLES is appended to the triangle list.
std::string cube_object(int id, const std::string& extra_triangles = "") {
  std::string xml = "<object id=\"" + std::to_string(id) + "\" type=\"model\"><mesh><vertices>";
  for (int i = 0; i < 8; ++i) {
    xml += "<vertex x=\"" + std::to_string(i & 1) + "\" y=\"" + std::to_string((i >> 1) & 1) + "\" z=\"" +
           std::to_string((i >> 2) & 1) + "\"/>";
  }
  xml += "</vertices><triangles>";
  // Vertex i = (x, y, z) bits; two triangles per face, counter-clockwise seen from outside.
  const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) {
    xml += "<triangle v1=\"" + std::to_string(f[0]) + "\" v2=\"" + std::to_string(f[1]) + "\" v3=\"" +
           std::to_string(f[2]) + "\"/>";
  }
  return xml + extra_triangles + "</triangles></mesh></object>";
}

core::Box3 bounds(const RawMesh& mesh) {
  core::Box3 box;
  for (const core::Vec3& p : mesh.points) box.add(p);
  return box;
}

double signed_volume(const RawMesh& mesh) {
  double six_volume = 0.0;
  for (const Triangle& t : mesh.triangles) {
    six_volume += core::dot(mesh.points[t[0]], core::cross(mesh.points[t[1]], mesh.points[t[2]]));
  }
  return six_volume / 6.0;
}

// Coordinates in these tests are small integers and float-exact, so boxes compare exactly.
void expect_box(const RawMesh& mesh, core::Vec3 min, core::Vec3 max) {
  const core::Box3 box = bounds(mesh);
  EXPECT_EQ(box.min, min) << box.min.x << " " << box.min.y << " " << box.min.z;
  EXPECT_EQ(box.max, max) << box.max.x << " " << box.max.y << " " << box.max.z;
}

void expect_error(const core::Result<ReadResult>& result, const std::string& word) {
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find(word), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("part.3mf"), std::string::npos) << result.error().message;
}

TEST(Read3mf, UnitCube) {
  const auto result = read_3mf(package(model_xml(cube_object(1), R"(<item objectid="1"/>)")), "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  const ReadResult& read = result.value();
  EXPECT_EQ(read.format, Format::k3mf);
  EXPECT_EQ(read.mesh.points.size(), 8u);
  EXPECT_EQ(read.mesh.triangles.size(), 12u);
  EXPECT_TRUE(read.warnings.empty());
  expect_box(read.mesh, {0, 0, 0}, {1, 1, 1});
  EXPECT_DOUBLE_EQ(signed_volume(read.mesh), 1.0);
}

TEST(Read3mf, BuildItemTranslation) {
  // 3MF transforms are "m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32", the last three the
  // translation.
  const auto result = read_3mf(
      package(model_xml(cube_object(1), R"(<item objectid="1" transform="1 0 0 0 1 0 0 0 1 10 20 30"/>)")),
      "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  expect_box(result.value().mesh, {10, 20, 30}, {11, 21, 31});
}

TEST(Read3mf, BuildItemRotationKeepsOrientation) {
  // 90 degrees about z: x -> y, y -> -x (row-vector convention: p' = p M).
  const auto result = read_3mf(
      package(model_xml(cube_object(1), R"(<item objectid="1" transform="0 1 0 -1 0 0 0 0 1 0 0 0"/>)")),
      "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  expect_box(result.value().mesh, {-1, 0, 0}, {0, 1, 1});
  EXPECT_DOUBLE_EQ(signed_volume(result.value().mesh), 1.0);
}

TEST(Read3mf, ComponentsReferencingOneMeshTwice) {
  const std::string components = R"(<object id="2" type="model"><components>
      <component objectid="1" transform="1 0 0 0 1 0 0 0 1 2 0 0"/>
      <component objectid="1" transform="1 0 0 0 1 0 0 0 1 0 0 5"/>
    </components></object>)";
  const auto result =
      read_3mf(package(model_xml(cube_object(1) + components, R"(<item objectid="2"/>)")), "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result.value().mesh.triangles.size(), 24u);
  EXPECT_EQ(result.value().mesh.points.size(), 16u);
  expect_box(result.value().mesh, {0, 0, 0}, {3, 1, 6});
  EXPECT_DOUBLE_EQ(signed_volume(result.value().mesh), 2.0);
}

TEST(Read3mf, ComponentTransformAppliesBeforeBuildItemTransform) {
  // Component: translate x by 5. Build item: scale by 2. Build space = 2 * (p + 5) in x.
  const std::string components = R"(<object id="2" type="model"><components>
      <component objectid="1" transform="1 0 0 0 1 0 0 0 1 5 0 0"/></components></object>)";
  const auto result = read_3mf(
      package(model_xml(cube_object(1) + components, R"(<item objectid="2" transform="2 0 0 0 2 0 0 0 2 0 0 0"/>)")),
      "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  expect_box(result.value().mesh, {10, 0, 0}, {12, 2, 2});
}

TEST(Read3mf, NestedComponentsAndTwoBuildItems) {
  const std::string objects = cube_object(1) +
                              R"(<object id="2" type="model"><components><component objectid="1"/></components></object>
      <object id="3" type="model"><components><component objectid="2" transform="1 0 0 0 1 0 0 0 1 0 3 0"/>
      </components></object>)";
  const auto result = read_3mf(
      package(model_xml(objects, R"(<item objectid="3"/><item objectid="1" transform="1 0 0 0 1 0 0 0 1 -4 0 0"/>)")),
      "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result.value().mesh.triangles.size(), 24u);
  expect_box(result.value().mesh, {-4, 0, 0}, {1, 4, 1});
}

TEST(Read3mf, ModelUnitIsConvertedToMillimetres) {
  const auto result =
      read_3mf(package(model_xml(cube_object(1), R"(<item objectid="1"/>)", "centimeter")), "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  expect_box(result.value().mesh, {0, 0, 0}, {10, 10, 10});
}

TEST(Read3mf, NotAZipArchive) {
  expect_error(read_3mf("solid cube\nendsolid cube\n", "part.3mf"), "not a zip");
  expect_error(read_3mf("", "part.3mf"), "not a zip");
}

TEST(Read3mf, MissingModelPart) {
  expect_error(read_3mf(make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels}}), "part.3mf"),
               "model part");
}

TEST(Read3mf, IndexBeyondVertexCount) {
  const auto result = read_3mf(
      package(model_xml(cube_object(7, R"(<triangle v1="0" v2="1" v3="8"/>)"), R"(<item objectid="7"/>)")),
      "part.3mf");
  expect_error(result, "vertex count 8");
  EXPECT_NE(result.error().message.find("object 7, triangle 12"), std::string::npos) << result.error().message;
}

TEST(Read3mf, ComponentCycle) {
  const std::string objects =
      R"(<object id="1" type="model"><components><component objectid="2"/></components></object>
      <object id="2" type="model"><components><component objectid="1"/></components></object>)";
  expect_error(read_3mf(package(model_xml(objects, R"(<item objectid="2"/>)")), "part.3mf"), "cycle");
  const std::string self = R"(<object id="3" type="model"><components><component objectid="3"/></components></object>)";
  expect_error(read_3mf(package(model_xml(self, R"(<item objectid="3"/>)")), "part.3mf"), "cycle");
}

// Objects 2..LEVELS+1, each using the previous one COPIES times: COPIES^LEVELS instances of the cube.
std::string component_tower(int levels, int copies) {
  std::string objects = cube_object(1);
  for (int id = 2; id <= levels + 1; ++id) {
    objects += "<object id=\"" + std::to_string(id) + "\" type=\"model\"><components>";
    for (int c = 0; c < copies; ++c) objects += "<component objectid=\"" + std::to_string(id - 1) + "\"/>";
    objects += "</components></object>";
  }
  return model_xml(objects, "<item objectid=\"" + std::to_string(levels + 1) + "\"/>");
}

TEST(Read3mf, ComponentExpansionIsRefusedBeforeLib3mfWalksIt) {
  // 2^40 instances in about 1.5 kB; lib3mf 1.8 alone would walk every one of them for hours.
  expect_error(read_3mf(package(component_tower(40, 2)), "part.3mf"), "component instances");
  // lib3mf walks the tree once per build item: 64 items of 2^15 instances each is 2^21 in all.
  std::string model = component_tower(15, 2);
  std::string items;
  for (int i = 0; i < 64; ++i) items += "<item objectid=\"16\"/>";
  model.replace(model.find("<item"), std::string("<item objectid=\"16\"/>").size(), items);
  expect_error(read_3mf(package(model), "part.3mf"), "build items expand");
}

TEST(Read3mf, DeepComponentNestingIsRefused) {
  expect_error(read_3mf(package(component_tower(100, 1)), "part.3mf"), "nest deeper");
  const auto ok = read_3mf(package(component_tower(30, 1)), "part.3mf");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(ok.value().mesh.triangles.size(), 12u);
}

TEST(Read3mf, SingularBuildItemTransform) {
  expect_error(
      read_3mf(package(model_xml(cube_object(1), R"(<item objectid="1" transform="1 0 0 0 1 0 0 0 0 0 0 0"/>)")),
               "part.3mf"),
      "singular");
}

TEST(Read3mf, SingularComponentTransform) {
  const std::string components = R"(<object id="2" type="model"><components>
      <component objectid="1" transform="1 0 0 2 0 0 0 0 1 0 0 0"/></components></object>)";
  expect_error(read_3mf(package(model_xml(cube_object(1) + components, R"(<item objectid="2"/>)")), "part.3mf"),
               "singular");
}

TEST(Read3mf, ZipBombIsRefusedBeforeInflating) {
  // 64 MiB of zeros deflate to about 64 kB: a ratio near deflate's maximum of 1032:1.
  const std::string zeros(64u << 20, '\0');
  const std::string archive = make_zip({{"[Content_Types].xml", kContentTypes},
                                        {"_rels/.rels", kRels},
                                        {"3D/3dmodel.model", model_xml(cube_object(1), R"(<item objectid="1"/>)")},
                                        {"Metadata/padding.bin", zeros}});
  ASSERT_LT(archive.size(), 100'000u);
  expect_error(read_3mf(archive, "part.3mf"), "zip bomb");
}

TEST(Read3mf, DegenerateTriangleIsDroppedWithWarning) {
  const std::string model =
      model_xml(cube_object(4, R"(<triangle v1="0" v2="0" v3="5"/>)"), R"(<item objectid="4"/>)");
  const auto result = read_3mf(package(model), "part.3mf");
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result.value().mesh.triangles.size(), 12u);
  ASSERT_EQ(result.value().warnings.size(), 1u);
  const std::string& warning = result.value().warnings[0];
  EXPECT_NE(warning.find("degenerate"), std::string::npos) << warning;
  EXPECT_NE(warning.find("object 4"), std::string::npos) << warning;
  EXPECT_NE(warning.find("triangle 12"), std::string::npos) << warning;
  EXPECT_DOUBLE_EQ(signed_volume(result.value().mesh), 1.0);

  ReadOptions strict;
  strict.strict = true;
  expect_error(read_3mf(package(model), "part.3mf", strict), "degenerate");
}

TEST(Read3mf, NoBuildItem) {
  expect_error(read_3mf(package(model_xml(cube_object(1), "")), "part.3mf"), "build item");
}

TEST(Read3mf, TriangleCapCountsComponentInstances) {
  const std::string components = R"(<object id="2" type="model"><components>
      <component objectid="1"/><component objectid="1" transform="1 0 0 0 1 0 0 0 1 0 0 5"/>
    </components></object>)";
  const std::string archive = package(model_xml(cube_object(1) + components, R"(<item objectid="2"/>)"));
  ReadOptions options;
  options.max_triangles = 20;  // 12 triangle elements in the file, 24 once instanced
  expect_error(read_3mf(archive, "part.3mf", options), "max-triangles");
  options.max_triangles = 10;  // refused by the scan, before lib3mf parses
  expect_error(read_3mf(archive, "part.3mf", options), "max-triangles");
  options.max_triangles = 24;
  EXPECT_TRUE(read_3mf(archive, "part.3mf", options).ok());
}

TEST(Read3mf, EveryTruncatedPrefixFailsCleanly) {
  const std::string archive = package(model_xml(cube_object(1), R"(<item objectid="1"/>)"));
  for (std::size_t n = 0; n < archive.size(); ++n) {
    const auto result = read_3mf(std::string_view(archive).substr(0, n), "part.3mf");
    ASSERT_FALSE(result.ok()) << "prefix " << n;
    EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput) << "prefix " << n;
  }
}

}  // namespace
}  // namespace polyaxis::io
