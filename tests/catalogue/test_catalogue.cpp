// RELIABILITY.md, file-level (F1–F17) and topology (T1–T9) rows: each test makes its input, runs
// `polyaxis inspect` on it and checks the exit code and the message.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zip.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <regex>
#include <vector>

#include "support/cli.h"
#include "support/meshes.h"

namespace polyaxis::test {
namespace {

bool contains(const std::string& text, const std::string& word) { return text.find(word) != std::string::npos; }

class Catalogue : public testing::Test {
 protected:
  std::string file(const std::string& name, const std::string& bytes) {
    const auto p = dir_ / name;
    write_file(p, bytes);
    return "'" + p.string() + "'";
  }
  CliRun inspect(const std::string& quoted_path, const std::string& extra = "") {
    return run_cli("inspect " + quoted_path + " --json " + extra);
  }
  TempDir dir_;
};

// Overwrites the float at byte offset OFFSET of a binary STL.
void put_float(std::string& bytes, std::size_t offset, float value) { std::memcpy(bytes.data() + offset, &value, 4); }
void put_u32(std::string& bytes, std::size_t offset, std::uint32_t value) { std::memcpy(bytes.data() + offset, &value, 4); }

TEST_F(Catalogue, F1_TruncatedBinary) {
  std::string bytes = binary_stl(cube());
  bytes.resize(bytes.size() - 17);
  const auto r = inspect(file("cut.stl", bytes));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "truncated: expected 684 bytes, got 667")) << r.err;
}

TEST_F(Catalogue, F2_HeaderCountDisagreesWithSize) {
  std::string bytes = binary_stl(cube());
  put_u32(bytes, 80, 4000000000u);  // never allocated from
  const auto r = inspect(file("count.stl", bytes));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "trusting the size")) << r.err;
  EXPECT_TRUE(contains(r.out, "\"triangles\": 12"));
}

TEST_F(Catalogue, F3_NoTriangles) {
  std::string empty_binary = binary_stl(RawMesh{});
  auto r = inspect(file("empty.stl", empty_binary));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "no geometry")) << r.err;
  r = inspect(file("empty_ascii.stl", "solid nothing\nendsolid nothing\n"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "no geometry")) << r.err;
}

TEST_F(Catalogue, F4_BinaryWithSolidHeader) {
  const auto r = inspect(file("solid.stl", binary_stl(cube(), "solid ascii-looking header")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"format\": \"stl-binary\""));
}

TEST_F(Catalogue, F5_SolidHeaderBinaryBodyAndCutAscii) {
  std::string bytes = binary_stl(cube(), "solid x\n  facet normal 0 0 0");
  auto r = inspect(file("mixed.stl", bytes));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string text = ascii_stl(cube());
  text.resize(text.size() * 2 / 3);
  r = inspect(file("cut_ascii.stl", text));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "line ")) << r.err;
  // Keywords in upper case are ASCII STL too (read as a binary header "claiming 538976266 triangles").
  std::string upper = ascii_stl(cube());
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  r = inspect(file("upper.stl", upper));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"triangles\": 12")) << r.out;
}

TEST_F(Catalogue, F6_NonFiniteVertexOrNormal) {
  std::string bytes = binary_stl(cube());
  put_float(bytes, 84 + 50 * 7 + 12 + 4, std::numeric_limits<float>::quiet_NaN());
  auto r = inspect(file("nan.stl", bytes));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "facet 7")) << r.err;
  std::string text = ascii_stl(cube());
  text.replace(text.find("vertex 0 0 0"), 12, "vertex 0 inf 0");
  r = inspect(file("inf.stl", text));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "facet 0")) << r.err;
  bytes = binary_stl(cube());
  put_float(bytes, 84 + 50 * 3, std::numeric_limits<float>::quiet_NaN());  // a normal
  r = inspect(file("nan_normal.stl", bytes));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "normals are recomputed")) << r.err;
}

TEST_F(Catalogue, F7_CoordinatesOutOfRange) {
  const auto r = inspect(file("far.stl", binary_stl(box({0, 0, 0}, {1e7, 1, 1}))));
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_TRUE(contains(r.err, "coordinates out of range")) << r.err;
}

TEST_F(Catalogue, F8_SuspectUnits) {
  auto r = inspect(file("tiny.stl", ascii_stl(cube(1e-4))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "--scale")) << r.err;
  r = inspect(file("metres.stl", binary_stl(cube(0.05))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "--scale 1000")) << r.err;
  r = inspect(file("metres2.stl", binary_stl(cube(0.05))), "--scale 1000");  // never rescaled silently
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_FALSE(contains(r.err, "--scale")) << r.err;
  EXPECT_TRUE(contains(r.out, "\"volume_mm3\": 125000")) << r.out;
}

TEST_F(Catalogue, F9_OpaqueNames) {
  std::string name(10000, 'n');
  name[5] = '\xff';
  name[6] = '\xfe';
  name[7] = '\0';
  auto r = inspect(file("name.stl", ascii_stl(cube(), name)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string header(80, '\0');
  header[0] = '\xc3';
  r = inspect(file("header.stl", binary_stl(cube(), header)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(Catalogue, F10_TooManyTriangles) {
  std::string bytes(84, ' ');
  put_u32(bytes, 80, 4000000000u);
  auto r = inspect(file("claims.stl", bytes + std::string(501, '\0')));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "exceeds --max-triangles")) << r.err;
  r = inspect(file("many.stl", binary_stl(cube())), "--max-triangles 10");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "exceeds --max-triangles")) << r.err;
  // A 10 GB binary STL (sparse: no disk used) is refused from its size and header, before it is
  // mapped (it was read whole, 9.7 GB resident, first).
  const auto big = dir_ / "big.stl";
  std::string header(84, ' ');
  put_u32(header, 80, 200'000'000u);
  write_file(big, header);
  std::filesystem::resize_file(big, 84 + 50ull * 200'000'000u);
  r = inspect("'" + big.string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "binary STL of 200000000 triangles (by its size")) << r.err;
}

TEST_F(Catalogue, F11_CompressedInput) {
  auto r = inspect(file("gz.stl", std::string("\x1f\x8b\x08\x00", 4) + std::string(200, 'x')));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "compressed input")) << r.err;
  EXPECT_TRUE(contains(r.err, "decompress first")) << r.err;
  r = inspect(file("zip.stl", std::string("PK\x03\x04", 4) + std::string(201, 'x')));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "compressed input")) << r.err;
}

TEST_F(Catalogue, F12_BomCrlfTabs) {
  auto r = inspect(file("bom_bin.stl", "\xEF\xBB\xBF" + binary_stl(cube())));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string text = ascii_stl(cube());
  std::string crlf;
  for (char c : text) {
    if (c == '\n') crlf += "\r\n";
    else if (c == ' ') crlf += '\t';
    else crlf += c;
  }
  r = inspect(file("crlf.stl", "\xEF\xBB\xBF" + crlf));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"volume_mm3\": 1000")) << r.out;
}

TEST_F(Catalogue, F13_AttributeBytes) {
  std::string bytes = binary_stl(cube());
  for (int t = 0; t < 12; ++t) bytes[84 + 50 * t + 48] = '\x1f', bytes[84 + 50 * t + 49] = '\x7c';
  const auto r = inspect(file("colour.stl", bytes));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(Catalogue, F14_ObjIndices) {
  const std::string verts = "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\n";
  const std::string quads = "f -8 -5 -6 -7\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  auto r = inspect(file("cube.obj", verts + quads));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"volume_mm3\": 1000")) << r.out;
  r = inspect(file("zero.obj", verts + "f 0 1 2\n"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "line 9")) << r.err;
  r = inspect(file("range.obj", verts + "f 1 2 9\n"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "out of range")) << r.err;
  r = inspect(file("nov.obj", "f 1 2 3\n"));
  EXPECT_EQ(r.exit_code, 3);
}

// A zip archive in memory (libzip), entries given as name/content pairs.
std::string make_zip(const std::vector<std::pair<std::string, std::string>>& entries) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* src = zip_source_buffer_create(nullptr, 0, 0, &error);
  zip_t* za = zip_open_from_source(src, ZIP_TRUNCATE, &error);
  zip_source_keep(src);
  for (const auto& [name, content] : entries) {
    zip_source_t* s = zip_source_buffer(za, content.data(), content.size(), 0);
    zip_file_add(za, name.c_str(), s, ZIP_FL_OVERWRITE);
  }
  zip_close(za);
  zip_source_open(src);
  zip_source_seek(src, 0, SEEK_END);
  const auto size = static_cast<std::size_t>(zip_source_tell(src));
  zip_source_seek(src, 0, SEEK_SET);
  std::string out(size, '\0');
  zip_source_read(src, out.data(), size);
  zip_source_close(src);
  zip_source_free(src);
  return out;
}

const char* kContentTypes =
    R"(<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">)"
    R"(<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>)"
    R"(<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>)";
const char* kRels =
    R"(<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">)"
    R"(<Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>)";

std::string model_xml(const std::string& triangles) {
  return R"(<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">)"
         R"(<resources><object id="1" type="model"><mesh><vertices>)"
         R"(<vertex x="0" y="0" z="0"/><vertex x="10" y="0" z="0"/><vertex x="0" y="10" z="0"/><vertex x="0" y="0" z="10"/>)"
         R"(</vertices><triangles>)" +
         triangles + R"(</triangles></mesh></object></resources><build><item objectid="1"/></build></model>)";
}

const char* kTetra = R"(<triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/><triangle v1="1" v2="2" v3="3"/><triangle v1="0" v2="3" v3="2"/>)";

TEST_F(Catalogue, F15_ThreeMf) {
  auto r = inspect(file("tetra.3mf", make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels},
                                               {"3D/3dmodel.model", model_xml(kTetra)}})));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"format\": \"3mf\"")) << r.out;
  r = inspect(file("nomodel.3mf", make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels}})));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  r = inspect(file("index.3mf", make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels},
                                          {"3D/3dmodel.model", model_xml(R"(<triangle v1="0" v2="2" v3="9"/>)")}})));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  r = inspect(file("bomb.3mf", make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels},
                                         {"3D/3dmodel.model", model_xml(kTetra)}, {"3D/pad.bin", std::string(64u << 20, '\0')}})));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  r = inspect(file("notzip.3mf", "this is not a zip archive at all"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  // A coordinate that is not a number was read as 0 with a warning (a different part): 3, naming
  // the vertex. Signs, fractions and exponents are numbers.
  for (const std::string bad : {R"(x="abc")", R"(x="")", R"(x="nan")", R"(x="1e999")", R"(x="1,5")"}) {
    std::string xml = model_xml(kTetra);
    xml.replace(xml.find(R"(x="10")"), 6, bad);
    r = inspect(file("coord.3mf", make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels}, {"3D/3dmodel.model", xml}})));
    EXPECT_EQ(r.exit_code, 3) << bad << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "vertex 1")) << r.err;
  }
  std::string xml = model_xml(kTetra);
  xml.replace(xml.find(R"(x="10")"), 6, R"(x="+1.0e1")");
  r = inspect(file("coord.3mf", make_zip({{"[Content_Types].xml", kContentTypes}, {"_rels/.rels", kRels}, {"3D/3dmodel.model", xml}})));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// CAD that is not sewn: an IGES file of trimmed surfaces was refused as open ("a hole of 74
// edges"); its faces are sewn before meshing and the part comes out closed with no hole filled.
TEST_F(Catalogue, F16_UnsewnIgesComesOutClosed) {
  const auto r = inspect("'" + std::string(POLYAXIS_CORPUS_DIR) + "/unsewn_fused.igs'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"watertight\": true")) << r.out;
  EXPECT_TRUE(contains(r.err, "sewn")) << r.err;
  EXPECT_FALSE(contains(r.err, "hole")) << r.err;
}

TEST_F(Catalogue, F16_StepFailures) {
  auto r = inspect(file("bad.step", "ISO-10303-21;\nHEADER;\nthis is not step\nENDSEC;\n"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "STEP")) << r.err;
  r = inspect(file("empty.step", "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "STEP")) << r.err;
  r = run_cli("inspect '" + std::string(POLYAXIS_CORPUS_DIR) + "/cube.step' --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"watertight\": true")) << r.out;
  setenv("POLYAXIS_CAD_TEST_CRASH", "1", 1);
  r = run_cli("inspect '" + std::string(POLYAXIS_CORPUS_DIR) + "/cube.step'");
  unsetenv("POLYAXIS_CAD_TEST_CRASH");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "crashed")) << r.err;
}

TEST_F(Catalogue, F17_NotARegularFile) {
  auto r = inspect("'" + dir_.path().string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "directory")) << r.err;
  const auto fifo = dir_ / "pipe.stl";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  r = inspect("'" + fifo.string() + "'");  // must not block waiting for a writer
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "not a regular file")) << r.err;
  r = inspect("/dev/zero");
  EXPECT_EQ(r.exit_code, 3);
  r = inspect("'" + (dir_ / "missing.stl").string() + "'");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.err, "cannot open")) << r.err;
  if (geteuid() != 0) {  // root reads any file
    const std::string locked = file("locked.stl", binary_stl(cube()));
    chmod((dir_ / "locked.stl").c_str(), 0);
    r = inspect(locked);
    EXPECT_EQ(r.exit_code, 3);
  }
}

TEST_F(Catalogue, T1_Holes) {
  RawMesh m = torus(20, 5, 40, 20);
  m.triangles.erase(m.triangles.begin() + 50, m.triangles.begin() + 52);
  auto r = inspect(file("hole.stl", binary_stl(m)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "1 holes filled")) << r.err;
  EXPECT_TRUE(contains(r.out, "\"watertight\": true"));
  RawMesh big = torus(20, 5, 40, 20);
  big.triangles.resize(big.triangles.size() - 80);
  r = inspect(file("open.stl", binary_stl(big)), "--max-hole-edges 10");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_TRUE(contains(r.err, "--allow-open")) << r.err;
  r = inspect(file("open2.stl", binary_stl(big)), "--max-hole-edges 10 --allow-open");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "left open")) << r.err;
}

TEST_F(Catalogue, T2_NonManifoldEdge) {
  const auto r = inspect(file("nm.stl", binary_stl(join(cube(), box({10, 10, 0}, {20, 20, 10})))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "1 non-manifold edges")) << r.err;
  EXPECT_TRUE(contains(r.out, "\"manifold\": true"));
}

TEST_F(Catalogue, T3_FlippedAndInsideOut) {
  RawMesh m = cube();
  std::swap(m.triangles[0][1], m.triangles[0][2]);
  auto r = inspect(file("flip.stl", ascii_stl(m)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "1 faces flipped")) << r.err;
  r = inspect(file("inside_out.stl", ascii_stl(flipped(cube()))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "inside-out")) << r.err;
  EXPECT_TRUE(contains(r.out, "\"volume_mm3\": 1000")) << r.out;
}

TEST_F(Catalogue, T4_DuplicateFaces) {
  RawMesh m = cube();
  m.triangles.push_back(m.triangles[2]);
  const auto r = inspect(file("dup.stl", binary_stl(m)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "1 duplicate faces removed")) << r.err;
}

TEST_F(Catalogue, T5_DegenerateFaces) {
  RawMesh m = cube();
  m.triangles.push_back({0, 1, 0});
  const auto r = inspect(file("degen.stl", binary_stl(m)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "1 degenerate faces removed")) << r.err;
}

TEST_F(Catalogue, T6_SelfIntersections) {
  const std::string p = file("overlap.stl", binary_stl(join(cube(), box({5, 5, 5}, {15, 15, 15}))));
  auto r = inspect(p);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "self-intersecting faces")) << r.err;
  r = inspect(p, "--strict");
  EXPECT_EQ(r.exit_code, 4);
  // Every command that reads a part honours --strict (plan, slice and analyze skipped the check).
  const std::string out = " -o '" + (dir_ / "out").string() + "'";
  for (const std::string& cmd : std::vector<std::string>{"plan " + p + out + " --no-html", "slice " + p + out, "analyze " + p + out}) {
    r = run_cli(cmd + " --strict");
    EXPECT_EQ(r.exit_code, 4) << cmd << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "self-intersect")) << cmd << ": " << r.err;
  }
  EXPECT_EQ(run_cli("plan " + p + out + " --strict --no-self-intersections").exit_code, 2);
}

TEST_F(Catalogue, T7_DisjointShells) {
  const auto r = inspect(file("two.stl", binary_stl(join(cube(), box({20, 0, 0}, {30, 10, 10})))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"shells\": 2")) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST_F(Catalogue, T8_NestedShells) {
  auto r = inspect(file("void.stl", binary_stl(join(cube(), flipped(box({2, 2, 2}, {8, 8, 8}))))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"cavities\": 1")) << r.out;
  EXPECT_TRUE(contains(r.out, "\"volume_mm3\": 784")) << r.out;
  r = inspect(file("inner.stl", binary_stl(join(cube(), box({2, 2, 2}, {8, 8, 8})))));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "interior shells removed")) << r.err;
  EXPECT_TRUE(contains(r.out, "\"volume_mm3\": 1000")) << r.out;
}

TEST_F(Catalogue, T9_NearCoincidentVertices) {
  RawMesh m = soup(cube());
  for (std::size_t i = 0; i < m.points.size(); i += 2) m.points[i].y += 3e-5;
  const auto r = inspect(file("near.stl", ascii_stl(m)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"vertices\": 8")) << r.out;
  EXPECT_TRUE(contains(r.out, "\"watertight\": true")) << r.out;
}

TEST_F(Catalogue, UsageErrorsExitTwo) {
  EXPECT_EQ(run_cli("inspect").exit_code, 2);
  EXPECT_EQ(run_cli("frobnicate x.stl").exit_code, 2);
  EXPECT_EQ(run_cli("inspect x.stl --merge-mm -1").exit_code, 2);
  EXPECT_EQ(run_cli("inspect x.stl --scale nan").exit_code, 2);
  EXPECT_EQ(run_cli("inspect x.stl --merge-mm nan").exit_code, 2);
  EXPECT_EQ(run_cli("inspect x.stl --chordal-mm 1e999").exit_code, 2);
}

// P5 for every number option: CLI11's own checks let "nan" and "inf" through.
TEST_F(Catalogue, P5_NonFiniteOptionsExitTwo) {
  const std::string part = file("cube.stl", binary_stl(cube()));
  for (const std::string& args : std::vector<std::string>{"inspect " + part + " --self-supporting-deg nan", "analyze " + part + " --voxel-mm nan",
                                 "analyze " + part + " --break-angle-deg inf", "analyze " + part + " --self-supporting-deg nan",
                                 "slice " + part + " --layer nan", "slice " + part + " --layer 1e308", "slice " + part + " --min inf",
                                 "plan " + part + " --path-tolerance-mm nan", std::string("simulate x.ngc --path-tolerance-mm nan")}) {
    const CliRun run = run_cli(args);
    EXPECT_EQ(run.exit_code, 2) << args << ": " << run.err;
  }
}

// P7: JSON nested 60 000 deep crashed the parser (signal 11); now refused before parsing, as a
// config file (2) or as a plan (3).
TEST_F(Catalogue, P7_DeeplyNestedJson) {
  const std::string part = file("cube.stl", binary_stl(cube()));
  const std::string deep = file("deep.json", "{\"name\":" + std::string(60000, '[') + std::string(60000, ']') + "}");
  const std::string out = "'" + (dir_ / "out").string() + "'";
  for (const std::string& args : std::vector<std::string>{"plan " + part + " -o " + out + " --machine " + deep, "plan " + part + " -o " + out + " --process " + deep,
                                 "simulate x.ngc --machine " + deep}) {
    const CliRun run = run_cli(args);
    EXPECT_EQ(run.exit_code, 2) << args << ": " << run.err;
    EXPECT_TRUE(contains(run.err, "nested deeper than")) << run.err;
  }
  for (const std::string& args : std::vector<std::string>{"view " + deep + " -o " + out + ".html", "explain " + deep + " --layer 1"}) {
    const CliRun run = run_cli(args);
    EXPECT_EQ(run.exit_code, 3) << args << ": " << run.err;
    EXPECT_TRUE(contains(run.err, "nested deeper than")) << run.err;
  }
  // Nesting a config's usual depth is still read.
  EXPECT_EQ(run_cli("plan " + part + " -o " + out + " --no-html --strategy single --set 'process.rules.interleave=false'").exit_code, 0);
}

// P8: a process switch holds M-codes (with P, Q, E, S words) and G4 dwells only; absurd feeds
// are refused, naming the key, rather than failing later with 1 or writing F0.000000000060.
TEST_F(Catalogue, P8_ProcessSwitchesAndFeeds) {
  const std::string part = file("cube.stl", binary_stl(cube()));
  const std::string out = " -o '" + (dir_ / "out").string() + "' --no-html --strategy single";
  for (const std::string& set : std::vector<std::string>{"process.process_on=M64 P0 G0 Z-150", "process.process_on=M2", "process.process_off=M30",
                                "process.process_on=M64 P0 F-5", "process.process_on=G4", "process.process_on=M64 P-1"}) {
    const CliRun run = run_cli("plan " + part + out + " --set '" + set + "'");
    EXPECT_EQ(run.exit_code, 2) << set << ": " << run.err;
    EXPECT_TRUE(contains(run.err, "process_o")) << run.err;
  }
  for (const std::string& set : std::vector<std::string>{"process.deposit_feed_mm_s=1e-14", "process.deposit_feed_mm_s=1e-12", "process.travel_feed_mm_s=1e6",
                                "machine.feed.linear_max_mm_min=1e-300", "machine.feed.rotary_max_deg_min=1e-9"}) {
    const CliRun run = run_cli("plan " + part + out + " --set '" + set + "'");
    EXPECT_EQ(run.exit_code, 2) << set << ": " << run.err;
    EXPECT_TRUE(contains(run.err, set.substr(set.find('.') + 1, set.find('=') - set.find('.') - 1))) << run.err;
  }
  // A value that is not UTF-8 made the document unwritable: exit 1 (found by fuzz_config).
  const CliRun bad = run_cli("plan " + part + out + " --set \"$(printf 'process.process_on=M64 P0\\254')\"");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_TRUE(contains(bad.err, "UTF-8")) << bad.err;
  for (const std::string& set : std::vector<std::string>{"process.process_on=M3 S1000", "process.process_on=M64 P0 G4 P0.5"}) {
    const CliRun run = run_cli("plan " + part + out + " --set '" + set + "'");
    EXPECT_EQ(run.exit_code, 0) << set << ": " << run.err;
  }
}

// O5: what a command prints must reach stdout; a full device is an output failure (6), not 0.
TEST_F(Catalogue, O5_StdoutWriteErrorsExitSix) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string part = file("cube.stl", binary_stl(cube()));
  for (const std::string& args : std::vector<std::string>{"inspect " + part + " --json", "inspect " + part, "analyze " + part + " --json --no-skeleton"}) {
    const std::string cmd = std::string("'") + POLYAXIS_CLI + "' " + args + " >/dev/full 2>/dev/null";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << args;
    EXPECT_EQ(WEXITSTATUS(status), 6) << args;
  }
}

// The set id a plan's files carry: report.json's, plan.json's report's, and the G-code's first line's.
struct SetIds {
  std::string report, plan, gcode;
};
SetIds set_ids(const std::filesystem::path& dir, const std::string& stem) {
  SetIds ids;
  const std::string report = slurp(dir / "report.json"), plan = slurp(dir / "plan.json"), gcode = slurp(dir / (stem + ".ngc"));
  std::smatch m;
  if (std::regex_search(report, m, std::regex(R"re("set_id": *"([0-9a-f]+)")re"))) ids.report = m[1];
  if (std::regex_search(plan, m, std::regex(R"re("set_id": *"([0-9a-f]+)")re"))) ids.plan = m[1];
  const std::string first_line = gcode.substr(0, gcode.find('\n'));
  if (std::regex_search(first_line, m, std::regex(R"(set ([0-9a-f]+)\))"))) ids.gcode = m[1];
  return ids;
}

// O9: a run that fails leaves nothing under the final names (a directory named report.html made
// plan exit 6 with a whole .ngc, plan.json and report.json beside it).
TEST_F(Catalogue, O9_FailedRunLeavesNoOutput) {
  const std::string part = file("cube.stl", binary_stl(cube()));
  const auto out = dir_ / "out";
  std::filesystem::create_directories(out / "report.html");
  const CliRun run = run_cli("plan " + part + " -o '" + out.string() + "'");
  EXPECT_EQ(run.exit_code, 6) << run.err;
  for (const char* name : {"cube.ngc", "plan.json", "report.json"}) EXPECT_FALSE(std::filesystem::exists(out / name)) << name;
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    EXPECT_TRUE(e.path().filename() == "report.html" || e.path().filename() == ".polyaxis.lock") << e.path();
  }
}

// O9: the files of one plan carry one set id; two runs into one directory at once leave one
// run's set, never a mix (2 in 10 tries mixed before the lock); a killed run's leftovers are
// removed by the next run.
TEST_F(Catalogue, O9_OutputIsOneSet) {
  const std::string part = file("cube.stl", binary_stl(cube(20.0)));
  const auto out = dir_ / "out";
  std::filesystem::create_directories(out / ".polyaxis-run-999999999-0");  // no such process
  write_file(out / ".polyaxis-run-999999999-0" / "cube.ngc", "G0 X0\n");
  const std::string cli = std::string("'") + POLYAXIS_CLI + "' plan " + part + " -o '" + out.string() + "' --no-html -q";
  for (int round = 0; round < 6; ++round) {
    // Two different plans (tilted torch and not) at once, into the same directory.
    const std::string both = "(" + cli + " & " + cli + " --no-tilt --strategy single & wait) >/dev/null 2>&1";
    ASSERT_EQ(std::system(both.c_str()), 0);
    const SetIds ids = set_ids(out, "cube");
    ASSERT_FALSE(ids.report.empty());
    EXPECT_EQ(ids.report, ids.plan) << "round " << round;
    EXPECT_EQ(ids.report, ids.gcode) << "round " << round;
  }
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    EXPECT_EQ(e.path().filename().string().rfind(".polyaxis-run-", 0), std::string::npos) << e.path();
  }
  // The same run twice gives the same bytes, the id included.
  ASSERT_EQ(std::system((cli + " >/dev/null 2>&1").c_str()), 0);
  const std::string gcode = slurp(out / "cube.ngc"), report = slurp(out / "report.json"), plan = slurp(out / "plan.json");
  ASSERT_EQ(std::system((cli + " >/dev/null 2>&1").c_str()), 0);
  EXPECT_TRUE(slurp(out / "cube.ngc") == gcode);
  EXPECT_TRUE(slurp(out / "report.json") == report);
  EXPECT_TRUE(slurp(out / "plan.json") == plan);
}

// O3: a machine whose linear maximum is below the process's feeds slows every move: 0 with a
// warning counting the blocks (F100 on every move went without a word).
TEST_F(Catalogue, O3_SlowedFeedsAreWarned) {
  const std::string part = file("cube.stl", binary_stl(cube()));
  const std::string out = " -o '" + (dir_ / "out").string() + "' --no-html --strategy single";
  CliRun run = run_cli("plan " + part + out + " --set machine.feed.linear_max_mm_min=100");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(contains(run.err, "feed blocks run slower than planned")) << run.err;
  EXPECT_EQ(slurp(dir_ / "out" / "cube.ngc").find(" F3000"), std::string::npos);  // never above the limit
  run = run_cli("plan " + part + out);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_FALSE(contains(run.err, "run slower than planned")) << run.err;
}

// O5: --max-output-bytes caps what a plan writes: over it, 6 and nothing under the final names.
TEST_F(Catalogue, O5_MaxOutputBytes) {
  const std::string part = file("cube.stl", binary_stl(cube(20.0)));
  const auto out = dir_ / "out";
  for (const std::string cap : {"1000", "100000"}) {  // inside the G-code (72 kB), and past it (plan.json)
    const CliRun run = run_cli("plan " + part + " -o '" + out.string() + "' --max-output-bytes " + cap);
    EXPECT_EQ(run.exit_code, 6) << cap << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(out / "cube.ngc")) << cap;
    EXPECT_FALSE(std::filesystem::exists(out / "plan.json")) << cap;
  }
  EXPECT_EQ(run_cli("plan " + part + " -o '" + out.string() + "' --max-output-bytes -5").exit_code, 2);
  EXPECT_EQ(run_cli("plan " + part + " -o '" + out.string() + "' --no-html --max-output-bytes 100000000").exit_code, 0);
  EXPECT_TRUE(std::filesystem::exists(out / "cube.ngc"));
}

// O10: an output path that is a FIFO or a device is refused (6), not replaced by a regular file.
TEST_F(Catalogue, O10_NonRegularOutputRefused) {
  const std::string part = file("cube.stl", binary_stl(cube()));
  const auto out = dir_ / "out";
  ASSERT_EQ(run_cli("plan " + part + " -o '" + out.string() + "' --no-html").exit_code, 0);
  const auto fifo = dir_ / "fifo";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
  const CliRun run = run_cli("view '" + (out / "plan.json").string() + "' -o '" + fifo.string() + "'");
  EXPECT_EQ(run.exit_code, 6) << run.err;
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
}

}  // namespace
}  // namespace polyaxis::test
