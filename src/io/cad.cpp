// STEP/IGES reading isolated in a child process (RELIABILITY.md F16). OpenCASCADE can crash, loop
// or exhaust memory on a malformed file, so the import runs in a fork()ed child under RLIMIT_AS
// (options.import_memory_bytes) and RLIMIT_CPU, and the parent enforces a wall-clock limit
// (options.import_timeout_s) with SIGKILL. The child writes its result to an already-unlinked
// temporary file (mkostemp in the system temp directory, unlinked at once, so nothing is left
// behind on any path, even if the parent itself dies); the parent reads it back trusting no size
// in it beyond the file's own size.
//
// Result file layout (native byte order; the same machine writes and reads it):
//   "PAXCAD1\0", u32 status (0 ok, 1 error),
//   error: u64 length + message bytes;
//   ok:    u64 warning count, each u64 length + bytes; u64 point count, u64 triangle count,
//          points as 3 doubles (mm), triangles as 3 u32.
//
// Test hooks, read in the child only: POLYAXIS_CAD_TEST_CRASH=1 makes the child raise SIGSEGV
// before importing, POLYAXIS_CAD_TEST_HANG=1 makes it sleep forever, so tests can check the crash
// and timeout paths without a file that actually crashes OpenCASCADE.
//
// fork() without exec in a possibly multithreaded process: the child only calls the importer,
// which uses malloc (glibc makes malloc fork-safe) and no threads (BRepMesh runs sequentially).
#include "polyaxis/io/cad.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <new>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "cad_import.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;

constexpr char kMagic[8] = {'P', 'A', 'X', 'C', 'A', 'D', '1', '\0'};
constexpr std::uint32_t kStatusOk = 0;
constexpr std::uint32_t kStatusError = 1;

// Child exit codes.
constexpr int kExitOk = 0;
constexpr int kExitImportError = 3;   // an Error was written
constexpr int kExitWriteFailed = 4;   // the result file could not be written
constexpr int kExitException = 5;     // something escaped the importer's own catch
constexpr int kExitOutOfMemory = 6;   // std::bad_alloc escaped (RLIMIT_AS reached)

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

 private:
  int fd_;
};

// ---- child -------------------------------------------------------------------------------------

// Buffered writes to the result file; remembers the first failure.
class ResultWriter {
 public:
  explicit ResultWriter(int fd) : fd_(fd) { buffer_.reserve(kBufferBytes); }

  void put(const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0 && ok_) {
      const std::size_t n = std::min(size, kBufferBytes - buffer_.size());
      buffer_.insert(buffer_.end(), p, p + n);
      p += n;
      size -= n;
      if (buffer_.size() == kBufferBytes) flush();
    }
  }
  void put_u32(std::uint32_t v) { put(&v, sizeof v); }
  void put_u64(std::uint64_t v) { put(&v, sizeof v); }
  void put_string(std::string_view s) {
    put_u64(s.size());
    put(s.data(), s.size());
  }

  bool finish() {
    flush();
    return ok_;
  }

 private:
  static constexpr std::size_t kBufferBytes = 64u << 10;

  void flush() {
    std::size_t done = 0;
    while (done < buffer_.size() && ok_) {
      const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        ok_ = false;
        break;
      }
      done += static_cast<std::size_t>(n);
    }
    buffer_.clear();
  }

  int fd_;
  std::vector<char> buffer_;
  bool ok_ = true;
};

bool env_flag(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && std::string_view(value) == "1";
}

void set_limit(int resource, rlim_t soft, rlim_t hard) {
  rlimit limit{};
  limit.rlim_cur = soft;
  limit.rlim_max = hard;
  ::setrlimit(resource, &limit);  // best effort: a failure leaves the wall-clock limit in force
}

[[noreturn]] void run_child(int fd, const std::string& path, Format format, const ReadOptions& options) {
  // A crash must show up as WIFSIGNALED in the parent: default handlers (the parent, a test
  // framework or a sanitizer may have installed its own), nothing blocked, no core file.
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGXCPU, SIGTERM}) std::signal(sig, SIG_DFL);
  sigset_t all{};
  sigemptyset(&all);
  sigprocmask(SIG_SETMASK, &all, nullptr);
  set_limit(RLIMIT_CORE, 0, 0);
  // AddressSanitizer reserves terabytes of address space up front; an RLIMIT_AS would fail every
  // allocation of the child, so sanitized builds rely on the wall-clock limit alone.
  if (!kAddressSanitizer && options.import_memory_bytes > 0) {
    const auto bytes = static_cast<rlim_t>(options.import_memory_bytes);
    set_limit(RLIMIT_AS, bytes, bytes);
  }
  const double cpu_s = std::ceil(std::min(options.import_timeout_s, 1e7)) + 1.0;
  const auto cpu = static_cast<rlim_t>(cpu_s);
  set_limit(RLIMIT_CPU, cpu, cpu + 1);

  // OpenCASCADE reports its progress on stdout; keep the caller's output clean.
  const int devnull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (devnull >= 0) {
    ::dup2(devnull, STDOUT_FILENO);
    ::dup2(devnull, STDERR_FILENO);
  }

  if (env_flag("POLYAXIS_CAD_TEST_CRASH")) std::raise(SIGSEGV);
  if (env_flag("POLYAXIS_CAD_TEST_HANG")) {
    for (;;) ::pause();
  }

  try {
    std::vector<std::string> warnings;
    auto mesh_or = import_cad_file(path, format, options.chordal_mm, options.angular_deg, &warnings);
    ResultWriter out(fd);
    out.put(kMagic, sizeof kMagic);
    if (!mesh_or.ok()) {
      out.put_u32(kStatusError);
      out.put_string(mesh_or.error().message);
      ::_exit(out.finish() ? kExitImportError : kExitWriteFailed);
    }
    const RawMesh& mesh = mesh_or.value();
    out.put_u32(kStatusOk);
    out.put_u64(warnings.size());
    for (const std::string& w : warnings) out.put_string(w);
    out.put_u64(mesh.points.size());
    out.put_u64(mesh.triangles.size());
    for (const core::Vec3& p : mesh.points) {
      const double xyz[3] = {p.x, p.y, p.z};
      out.put(xyz, sizeof xyz);
    }
    static_assert(sizeof(Triangle) == 12);
    out.put(mesh.triangles.data(), mesh.triangles.size() * sizeof(Triangle));
    ::_exit(out.finish() ? kExitOk : kExitWriteFailed);
  } catch (const std::bad_alloc&) {
    ::_exit(kExitOutOfMemory);
  } catch (...) {
    ::_exit(kExitException);
  }
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

  const pid_t pid = ::fork();
  if (pid < 0) {
    return make_error(ErrorCode::kInternal, fmt::format("{} import of {}: cannot start the import process: {}", kind,
                                                        path, std::strerror(errno)));
  }
  if (pid == 0) run_child(fd, path, format, options);

  int wait_status = 0;
  if (!wait_for_child(pid, options.import_timeout_s, wait_status)) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import timed out after {:g} s on {}", kind, options.import_timeout_s, path));
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
  if (exit_code != kExitOk && exit_code != kExitImportError) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{} import failed on {}: the import process exited with code {}{}", kind, path,
                                  exit_code, exit_code == kExitWriteFailed ? " (cannot write its result)" : ""));
  }
  return read_child_result(fd, path, format, kind, options, exit_code);
}

}  // namespace polyaxis::io
