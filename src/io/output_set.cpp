#include "polyaxis/io/output_set.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <fmt/format.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace polyaxis::io {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kRunPrefix = ".polyaxis-run-";
// write_file_atomic's temporaries older than this are left over from a killed run.
constexpr auto kStaleTemporary = std::chrono::hours(1);

core::Error output_error(const std::string& what, const std::string& why) {
  return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: {}", what, why));
}

// True when NAME is a run directory whose process no longer exists.
bool stale_run(const std::string& name) {
  if (name.rfind(kRunPrefix, 0) != 0) return false;
  const std::string rest = name.substr(kRunPrefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == 0 || dash == std::string::npos) return false;
  long pid = 0;
  for (std::size_t i = 0; i < dash; ++i) {
    if (rest[i] < '0' || rest[i] > '9' || pid > 1'000'000'000) return false;
    pid = pid * 10 + (rest[i] - '0');
  }
  return pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

// True when NAME is a write_file_atomic temporary, `.X.tmp-` and six characters.
bool temporary_name(const std::string& name) {
  const std::size_t at = name.rfind(".tmp-");
  return name.size() > 1 && name[0] == '.' && at != std::string::npos && at > 1 && name.size() == at + 5 + 6;
}

void remove_stale(const fs::path& dir) {
  std::error_code ec;
  const auto now = fs::file_time_type::clock::now();
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    std::error_code ignored;
    if (stale_run(name)) {
      fs::remove_all(e.path(), ignored);
    } else if (temporary_name(name) && e.is_regular_file(ignored)) {
      const auto t = fs::last_write_time(e.path(), ignored);
      if (!ignored && now - t > kStaleTemporary) fs::remove(e.path(), ignored);
    }
  }
}

// Holds an exclusive flock on a file until destroyed.
class DirLock {
 public:
  explicit DirLock(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ >= 0) {
      while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
      }
    }
  }
  ~DirLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;
  bool ok() const { return fd_ >= 0; }

 private:
  int fd_;
};

}  // namespace

core::Result<OutputSet> OutputSet::open(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return output_error(dir, "cannot create: " + ec.message());
  if (!fs::is_directory(dir, ec)) return output_error(dir, "not a directory");
  remove_stale(dir);
  static std::atomic<unsigned> counter{0};
  const std::string run = (fs::path(dir) / fmt::format("{}{}-{}", kRunPrefix, ::getpid(), counter++)).string();
  fs::remove_all(run, ec);  // a leftover of a process that had this pid
  if (!fs::create_directory(run, ec) || ec) return output_error(dir, "cannot create a run directory: " + ec.message());
  return OutputSet(dir, run);
}

OutputSet::OutputSet(OutputSet&& other) noexcept
    : dir_(std::move(other.dir_)), run_dir_(std::move(other.run_dir_)), names_(std::move(other.names_)), done_(other.done_) {
  other.done_ = true;  // the moved-from set owns nothing
}

OutputSet::~OutputSet() {
  if (done_ || run_dir_.empty()) return;
  std::error_code ec;
  fs::remove_all(run_dir_, ec);
}

core::Status OutputSet::add(const std::string& name, std::string_view bytes, Durability durability) {
  if (name.empty() || name.find('/') != std::string::npos || name[0] == '.') {
    return output_error(name, "an output set holds plain file names");
  }
  if (auto s = write_file_atomic((fs::path(run_dir_) / name).string(), bytes, durability); !s) {
    return output_error((fs::path(dir_) / name).string(), s.error().message);
  }
  names_.push_back(name);
  return {};
}

core::Status OutputSet::commit() {
  DirLock lock((fs::path(dir_) / ".polyaxis.lock").string());
  if (!lock.ok()) return output_error(dir_, std::string("cannot lock the output directory: ") + std::strerror(errno));
  // Every final name must take a file before any is moved: a directory or a FIFO there would
  // otherwise leave half a set.
  for (const std::string& name : names_) {
    const std::string target = (fs::path(dir_) / name).string();
    struct stat st {};
    if (::lstat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
      return output_error(target, "exists and is not a regular file; nothing of this run was written");
    }
  }
  for (const std::string& name : names_) {
    const std::string from = (fs::path(run_dir_) / name).string(), to = (fs::path(dir_) / name).string();
    if (std::rename(from.c_str(), to.c_str()) != 0) return output_error(to, std::string("cannot move into place: ") + std::strerror(errno));
  }
  std::error_code ec;
  fs::remove_all(run_dir_, ec);
  done_ = true;
  return {};
}

}  // namespace polyaxis::io
