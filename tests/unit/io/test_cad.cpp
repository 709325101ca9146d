// read_cad: STEP and IGES through the OpenCASCADE child process (RELIABILITY.md F16).
// The corpus parts were written by OpenCASCADE's STEPControl_Writer / IGESControl_Writer from
// BRepPrimAPI_MakeBox(10, 10, 10) and BRepPrimAPI_MakeCylinder(5, 10).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include "polyaxis/core/vec3.h"
#include "polyaxis/io/cad.h"

#ifndef POLYAXIS_CORPUS_DIR
#error "POLYAXIS_CORPUS_DIR must name the tests/corpus directory"
#endif

namespace polyaxis::io {
namespace {

using core::ErrorCode;

std::string corpus(const char* name) { return std::string(POLYAXIS_CORPUS_DIR) + "/" + name; }

// Signed volume of a triangle soup (divergence theorem); positive for an outward-oriented solid.
double signed_volume(const RawMesh& mesh) {
  double six_volume = 0.0;
  for (const Triangle& t : mesh.triangles) {
    six_volume += core::dot(mesh.points[t[0]], core::cross(mesh.points[t[1]], mesh.points[t[2]]));
  }
  return six_volume / 6.0;
}

core::Box3 bounds(const RawMesh& mesh) {
  core::Box3 box;
  for (const core::Vec3& p : mesh.points) box.add(p);
  return box;
}

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~ScopedEnv() { ::unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

void expect_cube(const core::Result<ReadResult>& result, Format format) {
  ASSERT_TRUE(result.ok()) << result.error().message;
  const ReadResult& read = result.value();
  EXPECT_EQ(read.format, format);
  EXPECT_GE(read.mesh.points.size(), 8u);
  EXPECT_GT(read.mesh.triangles.size(), 0u);
  for (const Triangle& t : read.mesh.triangles) {
    for (const std::uint32_t i : t) ASSERT_LT(i, read.mesh.points.size());
  }
  // A box is meshed exactly: its planar faces are triangulated on their own corner points, so the
  // only error is the float rounding of writing and parsing "10." (none) and of the sums below.
  const core::Box3 box = bounds(read.mesh);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(box.min[axis], 0.0, 1e-6) << "axis " << axis;
    EXPECT_NEAR(box.max[axis], 10.0, 1e-6) << "axis " << axis;
  }
  EXPECT_NEAR(signed_volume(read.mesh), 1000.0, 1000.0 * 1e-6);
}

TEST(ReadCad, StepCube) { expect_cube(read_cad(corpus("cube.step"), Format::kStep), Format::kStep); }

TEST(ReadCad, IgesCube) { expect_cube(read_cad(corpus("cube.igs"), Format::kIges), Format::kIges); }

TEST(ReadCad, StepCylinderVolumeConvergesWithChordalTolerance) {
  // An inscribed polygonal cylinder is smaller than the true one (pi r^2 h = 250 pi = 785.398...);
  // the sagitta bound gives a relative area deficit of at most 2 * chordal / r.
  ReadOptions options;
  options.chordal_mm = 0.001;
  const auto result = read_cad(corpus("cylinder.step"), Format::kStep, options);
  ASSERT_TRUE(result.ok()) << result.error().message;
  const double exact = std::numbers::pi * 25.0 * 10.0;
  const double volume = signed_volume(result.value().mesh);
  EXPECT_LE(volume, exact + 1e-9);
  EXPECT_GE(volume, exact * (1.0 - 2.0 * options.chordal_mm / 5.0));
  const core::Box3 box = bounds(result.value().mesh);
  EXPECT_NEAR(box.min.z, 0.0, 1e-9);
  EXPECT_NEAR(box.max.z, 10.0, 1e-9);
}

TEST(ReadCad, StepSyntaxErrorIsInvalidInput) {
  const auto result = read_cad(corpus("bad_syntax.step"), Format::kStep);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("STEP"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("bad_syntax.step"), std::string::npos) << result.error().message;
}

TEST(ReadCad, IgesMessagesSayIges) {
  // A STEP file is not IGES: the IGES reader fails, and the message names the format it tried.
  const auto result = read_cad(corpus("bad_syntax.step"), Format::kIges);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("IGES"), std::string::npos) << result.error().message;
}

TEST(ReadCad, MissingFileIsInvalidInput) {
  const auto result = read_cad(corpus("no_such_file.step"), Format::kStep);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("no_such_file.step"), std::string::npos) << result.error().message;
}

TEST(ReadCad, DirectoryIsInvalidInput) {
  const auto result = read_cad(POLYAXIS_CORPUS_DIR, Format::kStep);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
}

TEST(ReadCad, CrashInsideImportIsReported) {
  const ScopedEnv crash("POLYAXIS_CAD_TEST_CRASH", "1");
  const auto result = read_cad(corpus("cube.step"), Format::kStep);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("crashed"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("signal 11"), std::string::npos) << result.error().message;
}

TEST(ReadCad, HangInsideImportTimesOut) {
  const ScopedEnv hang("POLYAXIS_CAD_TEST_HANG", "1");
  ReadOptions options;
  options.import_timeout_s = 1.0;
  const auto result = read_cad(corpus("cube.step"), Format::kStep, options);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("timed out"), std::string::npos) << result.error().message;
}

TEST(ReadCad, MemoryLimitStopsTheImport) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer builds do not set RLIMIT_AS in the import process";
#endif
  ReadOptions options;
  options.import_memory_bytes = 16u << 20;  // below what the loaded libraries already map
  const auto result = read_cad(corpus("cube.step"), Format::kStep, options);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("memory"), std::string::npos) << result.error().message;
}

TEST(ReadCad, EmptyDataSectionIsNoGeometry) {
  // A valid header and an empty DATA section: the "empty entity set" of F16.
  char path[] = "/tmp/polyaxis-test-empty-XXXXXX.step";
  const int fd = ::mkstemps(path, 5);
  ASSERT_GE(fd, 0);
  const std::string text =
      "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n"
      "FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n";
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd);
  const auto result = read_cad(path, Format::kStep);
  ::unlink(path);
  ASSERT_TRUE(written);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("STEP import failed"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("no solid or surface"), std::string::npos) << result.error().message;
}

TEST(ReadCad, TriangleCapIsEnforced) {
  ReadOptions options;
  options.max_triangles = 2;
  const auto result = read_cad(corpus("cube.step"), Format::kStep, options);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("max-triangles"), std::string::npos) << result.error().message;
}

TEST(ReadCad, RepeatedImportsLeakNoDescriptorsNorChildren) {
  const auto open_descriptors = [] {
    int count = 0;
    for (int fd = 0; fd < 1024; ++fd) {
      if (::fcntl(fd, F_GETFD) != -1) ++count;
    }
    return count;
  };
  const int before = open_descriptors();
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(read_cad(corpus("cube.step"), Format::kStep).ok());
    ASSERT_FALSE(read_cad(corpus("bad_syntax.step"), Format::kStep).ok());
  }
  EXPECT_EQ(open_descriptors(), before);
  // Every child was reaped: no zombie is left for this process to wait for.
  EXPECT_EQ(::waitpid(-1, nullptr, WNOHANG), -1);
}

}  // namespace
}  // namespace polyaxis::io
