// Output files written whole or not at all (RELIABILITY O5), also when made piece by piece
// (io::AtomicFile): nothing under the final name before commit(), no temporary left behind after a
// commit, a drop or a failure.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "polyaxis/io/write_file.h"

namespace polyaxis::io {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const char* name) {
  const fs::path d = fs::temp_directory_path() / (std::string("polyaxis_") + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t entries(const fs::path& d) { return static_cast<std::size_t>(std::distance(fs::directory_iterator(d), fs::directory_iterator())); }

TEST(AtomicFile, PiecesAppearTogetherOnCommitAndNotBefore) {
  const fs::path d = fresh_dir("atomic_pieces");
  const std::string path = (d / "out.json").string();
  {
    std::ofstream(path) << "old";
    auto f = AtomicFile::create(path);
    ASSERT_TRUE(f);
    ASSERT_TRUE(f.value().write("{\"a\":"));
    ASSERT_TRUE(f.value().write("1}"));
    EXPECT_EQ(read(path), "old");  // the old file stands until the commit
    ASSERT_TRUE(f.value().commit(Durability::kAtomic));
    EXPECT_FALSE(f.value().write("more"));  // closed
  }
  EXPECT_EQ(read(path), "{\"a\":1}");
  EXPECT_EQ(entries(d), 1u);  // no temporary left
  fs::remove_all(d);
}

TEST(AtomicFile, ADroppedFileLeavesNothing) {
  const fs::path d = fresh_dir("atomic_dropped");
  {
    auto f = AtomicFile::create((d / "out.json").string());
    ASSERT_TRUE(f);
    ASSERT_TRUE(f.value().write("half"));
    AtomicFile moved(std::move(f.value()));  // the moved-from file owns nothing
  }
  EXPECT_EQ(entries(d), 0u);
  fs::remove_all(d);
}

TEST(AtomicFile, RefusesWhatIsNotARegularFileAndAMissingDirectory) {
  const fs::path d = fresh_dir("atomic_refused");
  fs::create_directories(d / "taken");
  auto dir = AtomicFile::create((d / "taken").string());
  ASSERT_FALSE(dir);
  EXPECT_EQ(dir.error().code, core::ErrorCode::kOutput);
  auto missing = AtomicFile::create((d / "no" / "such" / "out.json").string());
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, core::ErrorCode::kOutput);
  EXPECT_EQ(entries(d), 1u);
  fs::remove_all(d);
}

}  // namespace
}  // namespace polyaxis::io
