// STEP/IGES reading isolated in a child process (RELIABILITY.md F16). OpenCASCADE can crash, loop
// or exhaust memory on a malformed file, so the import runs in a separate executable,
// polyaxis-cad-import (apps/polyaxis-cad-import, the only program linking OpenCASCADE, which also
// keeps ~30 ms of dynamic loading out of every CLI start). read_cad fork()s, sets RLIMIT_AS
// (options.import_memory_bytes) and RLIMIT_CPU in the child, and execv()s the helper; the parent
// enforces a wall-clock limit (options.import_timeout_s) with SIGKILL. The helper writes its result
// to an already-unlinked temporary file (mkostemp in the system temp directory, unlinked at once,
// so nothing is left behind on any path, even if the parent itself dies), inherited as a descriptor
// whose number is passed as --result-fd; the parent reads it back trusting no size in it beyond the
// file's own size. Layout and exit codes: cad_protocol in cad_import.h.
//
// Between fork() and execv() the child of a possibly multithreaded process calls only
// async-signal-safe functions: everything (argv, /dev/null, the limits) is prepared before fork().
// An execv() failure is reported through a close-on-exec pipe, so "cannot run the helper" is told
// apart from the helper's own exit codes.
//
// The helper is looked for, in this order, at $POLYAXIS_CAD_IMPORTER, next to the running
// executable (/proc/self/exe), next to the shared object holding this code (the installed
// libpolyaxis.so or the Python module, found with dladdr) and in ../bin from it, and at the
// build-tree path CMake bakes in (POLYAXIS_CAD_IMPORTER_DEFAULT). The test hooks POLYAXIS_CAD_TEST_CRASH / _HANG are read there.
#include "polyaxis/io/cad.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "cad_import.h"

#ifndef POLYAXIS_CAD_IMPORTER_DEFAULT
#define POLYAXIS_CAD_IMPORTER_DEFAULT ""
#endif

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;

namespace protocol = cad_protocol;
using protocol::kExitCannotLoad;
using protocol::kExitImportError;
using protocol::kExitOk;
using protocol::kExitOutOfMemory;
using protocol::kExitUsage;
using protocol::kExitWriteFailed;
using protocol::kMagic;
using protocol::kStatusError;
using protocol::kStatusOk;

constexpr const char* kImporterName = "polyaxis-cad-import";
constexpr const char* kImporterEnv = "POLYAXIS_CAD_IMPORTER";

constexpr std::uint64_t kMaxMessageBytes = 1u << 20;
constexpr std::uint64_t kMaxWarnings = 10'000;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// Closes a file descriptor on every path.
class UniqueFd {
 public:
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  void reset(int fd) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }

 private:
  int fd_;
};

// ---- locating and starting the helper -------------------------------------------------------

bool is_executable_file(const std::string& path) {
  struct stat st{};
  return !path.empty() && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

// $POLYAXIS_CAD_IMPORTER, next to the running executable, beside this shared object, then the build-tree default.
std::optional<std::string> find_importer() {
  if (const char* env = std::getenv(kImporterEnv); env != nullptr && is_executable_file(env)) return std::string(env);
  std::array<char, 4096> self{};
  const ssize_t n = ::readlink("/proc/self/exe", self.data(), self.size());
  if (n > 0 && static_cast<std::size_t>(n) < self.size()) {
    const std::filesystem::path beside =
        std::filesystem::path(std::string(self.data(), static_cast<std::size_t>(n))).parent_path() / kImporterName;
    if (is_executable_file(beside.string())) return beside.string();
  }
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&is_executable_file), &info) != 0 && info.dli_fname != nullptr) {
    const std::filesystem::path dir = std::filesystem::path(info.dli_fname).parent_path();
    for (const std::filesystem::path& candidate : {dir / kImporterName, dir / ".." / "bin" / kImporterName}) {
      if (is_executable_file(candidate.string())) return candidate.string();
    }
  }
  if (is_executable_file(POLYAXIS_CAD_IMPORTER_DEFAULT)) return std::string(POLYAXIS_CAD_IMPORTER_DEFAULT);
  return std::nullopt;
}

// Everything the child needs between fork() and execv(), prepared before fork() so that the child
// only makes async-signal-safe calls.
struct ChildPlan {
  std::string importer;
  std::vector<std::string> args;
  std::vector<char*> argv;  // into args, null-terminated
  // All three >= 3, so that pointing 0..2 at /dev/null in the child cannot clobber them.
  int result_fd = -1;       // close-on-exec cleared in the child only
  int devnull_fd = -1;      // stdin, stdout and stderr of the helper (-1: left as they are)
  int exec_error_fd = -1;   // write end of the close-on-exec pipe that reports an execv() errno
  bool limit_memory = false;
  rlim_t memory_bytes = 0;
  rlim_t cpu_s = 0;
};

void set_limit(int resource, rlim_t soft, rlim_t hard) {
  rlimit limit{};
  limit.rlim_cur = soft;
  limit.rlim_max = hard;
  ::setrlimit(resource, &limit);  // best effort: a failure leaves the wall-clock limit in force
}

[[noreturn]] void exec_child(const ChildPlan& plan) {
  // A crash must show up as WIFSIGNALED in the parent: default dispositions (execv keeps ignored
  // signals ignored), nothing blocked, no core file.
  struct sigaction default_action{};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGXCPU, SIGTERM, SIGPIPE, SIGCHLD}) {
    ::sigaction(sig, &default_action, nullptr);
  }
  sigset_t none{};
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  set_limit(RLIMIT_CORE, 0, 0);
  if (plan.limit_memory) set_limit(RLIMIT_AS, plan.memory_bytes, plan.memory_bytes);
  set_limit(RLIMIT_CPU, plan.cpu_s, plan.cpu_s + 1);

  // OpenCASCADE reports its progress on stdout; keep the caller's output clean.
  if (plan.devnull_fd >= 0) {
    for (const int stdio : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) ::dup2(plan.devnull_fd, stdio);
  }
#ifdef CLOSE_RANGE_CLOEXEC
  // No other descriptor of the parent reaches the helper (best effort; needs Linux 5.11).
  ::close_range(3, ~0u, CLOSE_RANGE_CLOEXEC);
#endif
  ::fcntl(plan.result_fd, F_SETFD, 0);  // the one descriptor the helper inherits

  ::execv(plan.importer.c_str(), plan.argv.data());
  const int error = errno;
  [[maybe_unused]] const ssize_t n = ::write(plan.exec_error_fd, &error, sizeof error);
  ::_exit(kExitCannotLoad);
}

// ---- parent ------------------------------------------------------------------------------------

// Reads the child's result file; every count is checked against the bytes actually present.
class ResultReader {
 public:
  ResultReader(int fd, std::uint64_t size) : fd_(fd), size_(size) {}

  std::uint64_t remaining() const { return size_ - offset_; }

  bool get(void* data, std::uint64_t size) {
    if (size > remaining()) return false;
    char* p = static_cast<char*>(data);
    std::uint64_t done = 0;
    while (done < size) {
      const ssize_t n = ::pread(fd_, p + done, static_cast<std::size_t>(size - done),
                                static_cast<off_t>(offset_ + done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      done += static_cast<std::uint64_t>(n);
    }
    offset_ += size;
    return true;
  }
  bool get_u32(std::uint32_t& v) { return get(&v, sizeof v); }
  bool get_u64(std::uint64_t& v) { return get(&v, sizeof v); }
  bool get_string(std::string& s, std::uint64_t max_bytes) {
    std::uint64_t length = 0;
    if (!get_u64(length) || length > max_bytes || length > remaining()) return false;
    s.resize(static_cast<std::size_t>(length));
    return get(s.data(), length);
  }

 private:
  int fd_;
  std::uint64_t size_;
  std::uint64_t offset_ = 0;
};

core::Result<ReadResult> read_child_result(int fd, const std::string& path, Format format, const char* kind,
                                           const ReadOptions& options, int exit_code) {
  const auto corrupt = [&](const char* what) {
    return make_error(ErrorCode::kInternal,
                      fmt::format("{} import of {}: the import process returned a bad result ({}, exit {})", kind,
                                  path, what, exit_code));
  };
  struct stat st{};
  if (::fstat(fd, &st) != 0 || st.st_size < 0) return corrupt("cannot stat the result file");
  ResultReader in(fd, static_cast<std::uint64_t>(st.st_size));

  char magic[sizeof kMagic] = {};
  std::uint32_t status = 0;
  if (!in.get(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0) return corrupt("no header");
  if (!in.get_u32(status)) return corrupt("no status");
  if (status == kStatusError) {
    std::string message;
    if (exit_code != kExitImportError || !in.get_string(message, kMaxMessageBytes)) return corrupt("bad message");
    return make_error(ErrorCode::kInvalidInput, message);
  }
  if (status != kStatusOk || exit_code != kExitOk) return corrupt("bad status");

  ReadResult result;
  result.format = format;
  std::uint64_t warning_count = 0;
  if (!in.get_u64(warning_count) || warning_count > kMaxWarnings) return corrupt("bad warning count");
  for (std::uint64_t i = 0; i < warning_count; ++i) {
    std::string warning;
    if (!in.get_string(warning, kMaxMessageBytes)) return corrupt("bad warning");
    result.warnings.push_back(std::move(warning));
  }
  std::uint64_t point_count = 0;
  std::uint64_t triangle_count = 0;
  if (!in.get_u64(point_count) || !in.get_u64(triangle_count)) return corrupt("no counts");
  if (triangle_count > options.max_triangles) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{}: {} tessellation has {} triangles, which exceeds --max-triangles {}", path,
                                  kind, triangle_count, options.max_triangles));
  }
  constexpr std::uint64_t kPointBytes = 3 * sizeof(double);
  constexpr std::uint64_t kTriangleBytes = sizeof(Triangle);
  if (point_count > in.remaining() / kPointBytes || triangle_count > in.remaining() / kTriangleBytes ||
      point_count * kPointBytes + triangle_count * kTriangleBytes != in.remaining() ||
      point_count > std::numeric_limits<std::uint32_t>::max()) {
    return corrupt("counts do not match the file size");
  }
  if (triangle_count == 0) {
    return make_error(ErrorCode::kInvalidInput, fmt::format("{} import failed: no geometry ({})", kind, path));
  }

  std::vector<double> coordinates(static_cast<std::size_t>(point_count) * 3);
  if (!in.get(coordinates.data(), point_count * kPointBytes)) return corrupt("short points");
  result.mesh.points.resize(static_cast<std::size_t>(point_count));
  for (std::size_t i = 0; i < result.mesh.points.size(); ++i) {
    const core::Vec3 p{coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]};
    if (!core::is_finite(p)) return corrupt("non-finite point");
    result.mesh.points[i] = p;
  }
  coordinates = {};
  result.mesh.triangles.resize(static_cast<std::size_t>(triangle_count));
  if (!in.get(result.mesh.triangles.data(), triangle_count * kTriangleBytes)) return corrupt("short triangles");
  for (const Triangle& t : result.mesh.triangles) {
    if (t[0] >= point_count || t[1] >= point_count || t[2] >= point_count) return corrupt("index out of range");
  }
  return result;
}

// Waits for PID up to TIMEOUT_S of wall-clock time; kills it with SIGKILL on expiry. Always reaps
// the child. Returns false on timeout.
bool wait_for_child(pid_t pid, double timeout_s, int& wait_status) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(std::min(timeout_s, 1e9)));
  auto pause = std::chrono::milliseconds(1);
  for (;;) {
    const pid_t r = ::waitpid(pid, &wait_status, WNOHANG);
    if (r == pid) return true;
    if (r < 0 && errno != EINTR) {
      // ECHILD: someone else reaped it (e.g. SIGCHLD ignored); report it as a failed import.
      wait_status = 0x7f00;  // WIFEXITED with a code no child uses
      return true;
    }
    if (Clock::now() >= deadline) break;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::milliseconds(50));
  }
  ::kill(pid, SIGKILL);
  while (::waitpid(pid, &wait_status, 0) < 0 && errno == EINTR) {
  }
  return false;
}

}  // namespace

core::Result<ReadResult> read_cad(const std::string& path, Format format, const ReadOptions& options) {
  if (format != Format::kStep && format != Format::kIges) {
    return make_error(ErrorCode::kUsage, fmt::format("read_cad({}): format is neither STEP nor IGES", path));
  }
  const char* kind = format == Format::kIges ? "IGES" : "STEP";
  if (!(options.import_timeout_s > 0.0)) {
    return make_error(ErrorCode::kUsage,
                      fmt::format("{} import of {}: timeout {} s must be positive", kind, path, options.import_timeout_s));
  }

  // Refuse what the child could block on (FIFO, device) or cannot read, with the reason.
  {
    const int probe = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (probe < 0) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{} import failed: cannot open {}: {}", kind, path, std::strerror(errno)));
    }
    UniqueFd probe_fd(probe);
    struct stat st{};
    if (::fstat(probe, &st) != 0 || !S_ISREG(st.st_mode)) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{} import failed: {} is not a regular file", kind, path));
    }
  }

  const std::optional<std::string> importer = find_importer();
  if (!importer) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import unavailable: {} not found (set {})", kind, kImporterName, kImporterEnv));
  }

  std::error_code ec;
  std::filesystem::path temp_dir = std::filesystem::temp_directory_path(ec);
  if (ec) temp_dir = "/tmp";
  std::string name = (temp_dir / "polyaxis-cad-XXXXXX").string();
  const int fd = ::mkostemp(name.data(), O_CLOEXEC);
  if (fd < 0) {
    return make_error(ErrorCode::kInternal, fmt::format("{} import of {}: cannot create a temporary file in {}: {}",
                                                        kind, path, temp_dir.string(), std::strerror(errno)));
  }
  UniqueFd result_fd(fd);
  ::unlink(name.c_str());  // the open descriptor keeps the data; no file is left behind on any path

  UniqueFd devnull(::open("/dev/null", O_RDWR | O_CLOEXEC));
  int exec_pipe[2] = {-1, -1};
  if (::pipe2(exec_pipe, O_CLOEXEC | O_NONBLOCK) != 0) {
    return make_error(ErrorCode::kInternal, fmt::format("{} import of {}: cannot start the import process: {}", kind,
                                                        path, std::strerror(errno)));
  }
  UniqueFd exec_read(exec_pipe[0]);
  UniqueFd exec_write(exec_pipe[1]);
  // If this process runs with a standard stream closed, these may have landed on 0..2, which the
  // child points at /dev/null: move them above.
  for (UniqueFd* moving : {&result_fd, &devnull, &exec_write}) {
    if (moving->get() < 0 || moving->get() > STDERR_FILENO) continue;
    const int moved = ::fcntl(moving->get(), F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
    if (moved < 0) {
      return make_error(ErrorCode::kInternal, fmt::format("{} import of {}: cannot start the import process: {}",
                                                          kind, path, std::strerror(errno)));
    }
    moving->reset(moved);
  }

  ChildPlan plan;
  plan.importer = *importer;
  plan.args = {kImporterName,
               "--format",
               format == Format::kIges ? "iges" : "step",
               "--chordal-mm",
               fmt::format("{}", options.chordal_mm),  // shortest round-trip form
               "--angular-deg",
               fmt::format("{}", options.angular_deg),
               "--result-fd",
               std::to_string(result_fd.get()),
               "--",
               path};
  for (std::string& arg : plan.args) plan.argv.push_back(arg.data());
  plan.argv.push_back(nullptr);
  plan.result_fd = result_fd.get();
  plan.devnull_fd = devnull.get();
  plan.exec_error_fd = exec_write.get();
  // AddressSanitizer reserves terabytes of address space up front; an RLIMIT_AS would fail every
  // allocation of the (equally sanitized) helper, so sanitized builds rely on the wall-clock limit.
  plan.limit_memory = !kAddressSanitizer && options.import_memory_bytes > 0;
  plan.memory_bytes = static_cast<rlim_t>(options.import_memory_bytes);
  plan.cpu_s = static_cast<rlim_t>(std::ceil(std::min(options.import_timeout_s, 1e7)) + 1.0);

  const pid_t pid = ::fork();
  if (pid < 0) {
    return make_error(ErrorCode::kInternal, fmt::format("{} import of {}: cannot start the import process: {}", kind,
                                                        path, std::strerror(errno)));
  }
  if (pid == 0) exec_child(plan);
  exec_write.reset(-1);  // so that the read end sees end-of-file once the child has exec'd or exited

  int wait_status = 0;
  if (!wait_for_child(pid, options.import_timeout_s, wait_status)) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import timed out after {:g} s on {}", kind, options.import_timeout_s, path));
  }
  // The child has ended: an execv() errno is in the pipe, or nothing (it ran the helper).
  int exec_errno = 0;
  ssize_t got = 0;
  while ((got = ::read(exec_read.get(), &exec_errno, sizeof exec_errno)) < 0 && errno == EINTR) {
  }
  if (got == static_cast<ssize_t>(sizeof exec_errno)) {
    if (exec_errno == ENOMEM) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{} import failed: out of memory starting {} (limit {} MiB) on {}", kind,
                                    *importer, options.import_memory_bytes >> 20, path));
    }
    return make_error(ErrorCode::kInvalidInput, fmt::format("{} import unavailable: cannot run {}: {} (set {})", kind,
                                                            *importer, std::strerror(exec_errno), kImporterEnv));
  }
  if (WIFSIGNALED(wait_status)) {
    const int sig = WTERMSIG(wait_status);
    if (sig == SIGXCPU) {
      return make_error(ErrorCode::kInvalidInput,
                        fmt::format("{} import timed out after {:g} s of CPU time on {}", kind,
                                    std::ceil(options.import_timeout_s) + 1.0, path));
    }
    return make_error(ErrorCode::kInvalidInput, fmt::format("{} import crashed (signal {}{}) on {}", kind, sig,
                                                            sig == SIGKILL ? ", possibly out of memory" : "", path));
  }
  const int exit_code = WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1;
  if (exit_code == kExitOutOfMemory) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import failed: out of memory (limit {} MiB) on {}", kind,
                                  options.import_memory_bytes >> 20, path));
  }
  if (exit_code == kExitCannotLoad) {
    // execv succeeded (nothing came through the pipe), so the dynamic loader failed: a missing
    // shared library, or the address-space limit reached while mapping OpenCASCADE.
    const std::string limit =
        plan.limit_memory ? fmt::format("; memory limit {} MiB", options.import_memory_bytes >> 20) : std::string();
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import failed on {}: {} could not load its shared libraries (exit {}{})", kind,
                                  path, *importer, exit_code, limit));
  }
  if (exit_code != kExitOk && exit_code != kExitImportError) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import failed on {}: the import process exited with code {}{}", kind, path,
                                  exit_code, exit_code == kExitWriteFailed ? " (cannot write its result)"
                                  : exit_code == kExitUsage   ? " (bad command line)"
                                                              : ""));
  }
  return read_child_result(result_fd.get(), path, format, kind, options, exit_code);
}

}  // namespace polyaxis::io
