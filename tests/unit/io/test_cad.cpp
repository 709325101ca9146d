// read_cad: STEP and IGES through the polyaxis-cad-import helper process (RELIABILITY.md F16).
// The corpus parts were written by OpenCASCADE's STEPControl_Writer / IGESControl_Writer from
// BRepPrimAPI_MakeBox(10, 10, 10) and BRepPrimAPI_MakeCylinder(5, 10).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>

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

// Writes an executable shell script with BODY to a fresh temporary file; removes it on scope exit.
class ScopedScript {
 public:
  explicit ScopedScript(const std::string& body) {
    const int fd = ::mkstemp(path_);
    if (fd < 0) return;
    ok_ = ::write(fd, body.data(), body.size()) == static_cast<ssize_t>(body.size()) && ::fchmod(fd, 0700) == 0;
    ::close(fd);
  }
  ~ScopedScript() { ::unlink(path_); }
  ScopedScript(const ScopedScript&) = delete;
  ScopedScript& operator=(const ScopedScript&) = delete;

  bool ok() const { return ok_; }
  const char* path() const { return path_; }

 private:
  char path_[32] = "/tmp/polyaxis-test-cad-XXXXXX";
  bool ok_ = false;
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

// IGES of trimmed surfaces (OpenCASCADE's default IGES mode) carries no topology: each face cut
// its own edges and the mesh had holes of 74 edges (refused as open). The faces are sewn first:
// no free edge is left (the catalogue's F16 test reads the same file through repair: watertight).
// (tests/corpus/unsewn_fused.cpp.txt made the file: a cylinder, a sphere and a tilted torus, fused.)
TEST(ReadCad, UnsewnIgesFacesAreSewn) {
  const auto result = read_cad(corpus("unsewn_fused.igs"), Format::kIges);
  ASSERT_TRUE(result.ok()) << result.error().message;
  bool sewn = false;
  for (const std::string& w : result.value().warnings) sewn = sewn || w.find("free edges before, 0 after") != std::string::npos;
  EXPECT_TRUE(sewn);
  // A solid's faces share their edges already: nothing to sew.
  const auto cube = read_cad(corpus("cube.step"), Format::kStep);
  ASSERT_TRUE(cube.ok());
  for (const std::string& w : cube.value().warnings) EXPECT_EQ(w.find("sewn"), std::string::npos) << w;
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

TEST(ReadCad, ImporterFromEnvironmentIsUsed) {
  // A stand-in helper that exits 0 without writing: read_cad ran it, and refuses its empty result.
  const ScopedScript fake("#!/bin/sh\nexit 0\n");
  ASSERT_TRUE(fake.ok());
  const ScopedEnv importer("POLYAXIS_CAD_IMPORTER", fake.path());
  const auto result = read_cad(corpus("cube.step"), Format::kStep);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInternal);
  EXPECT_NE(result.error().message.find("bad result"), std::string::npos) << result.error().message;
}

TEST(ReadCad, MissingImporterInEnvironmentFallsBackToTheBuiltOne) {
  const ScopedEnv importer("POLYAXIS_CAD_IMPORTER", "/nonexistent/polyaxis-cad-import");
  expect_cube(read_cad(corpus("cube.step"), Format::kStep), Format::kStep);
}

TEST(ReadCad, ImporterThatCannotBeExecutedIsReported) {
  // execv fails (ENOENT for the interpreter); the errno comes back through the exec pipe.
  const ScopedScript broken("#!/nonexistent/interpreter\n");
  ASSERT_TRUE(broken.ok());
  const ScopedEnv importer("POLYAXIS_CAD_IMPORTER", broken.path());
  const auto result = read_cad(corpus("cube.step"), Format::kStep);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().code, ErrorCode::kInvalidInput);
  EXPECT_NE(result.error().message.find("cannot run"), std::string::npos) << result.error().message;
  EXPECT_NE(result.error().message.find("No such file"), std::string::npos) << result.error().message;
}

TEST(ReadCad, HelperInheritsTheResultDescriptorAndNoOther) {
  // A stand-in helper that fails unless the descriptor named by --result-fd is open and a
  // descriptor this process opened without O_CLOEXEC is not.
  const ScopedScript probe(
      "#!/bin/sh\n"
      "while [ \"$1\" != --result-fd ]; do shift; done\n"
      "[ -e /proc/$$/fd/$2 ] || exit 11\n"
      "[ ! -e /proc/$$/fd/$POLYAXIS_TEST_LEAKY_FD ] || exit 12\n"
      "exit 0\n");
  ASSERT_TRUE(probe.ok());
  const int leaky = ::open("/dev/null", O_RDONLY);  // deliberately without O_CLOEXEC
  ASSERT_GE(leaky, 0);
  const std::string leaky_name = std::to_string(leaky);
  const ScopedEnv leaky_env("POLYAXIS_TEST_LEAKY_FD", leaky_name.c_str());
  const ScopedEnv importer("POLYAXIS_CAD_IMPORTER", probe.path());
  const auto result = read_cad(corpus("cube.step"), Format::kStep);
  ::close(leaky);
  ASSERT_FALSE(result.ok());
  // Exit 0 without a header is the "bad result" of a probe that found what it expected.
  EXPECT_NE(result.error().message.find("no header, exit 0"), std::string::npos) << result.error().message;
}

TEST(ReadCad, WorksWithStandardStreamsClosed) {
  // The result file, /dev/null and the exec pipe then open on 0..2, which the child points at
  // /dev/null; read_cad must move them out of the way. Run in a child so this process keeps its
  // streams; the helper's streams are checked by a stand-in, the import by the real helper.
  const ScopedScript probe(
      "#!/bin/sh\n"
      "while [ \"$1\" != --result-fd ]; do shift; done\n"
      "[ -e /proc/$$/fd/$2 ] || exit 11\n"
      "for fd in 0 1 2; do [ \"$(readlink /proc/$$/fd/$fd)\" = /dev/null ] || exit 13; done\n"
      "exit 0\n");
  ASSERT_TRUE(probe.ok());
  const std::string cube = corpus("cube.step");
  const std::string probe_path = probe.path();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::close(STDIN_FILENO);
    ::close(STDOUT_FILENO);
    ::close(STDERR_FILENO);
    const auto imported = read_cad(cube, Format::kStep);
    if (!imported.ok() || imported.value().mesh.triangles.size() != 12) ::_exit(1);
    ::setenv("POLYAXIS_CAD_IMPORTER", probe_path.c_str(), 1);
    const auto probed = read_cad(cube, Format::kStep);
    ::_exit(!probed.ok() && probed.error().message.find("no header, exit 0") != std::string::npos ? 0 : 2);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: import failed, 2: the helper's streams or result fd were wrong";
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
