#include "polyaxis/io/read_part.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "polyaxis/io/cad.h"
#include "polyaxis/io/obj.h"
#include "polyaxis/io/stl.h"
#include "polyaxis/io/three_mf.h"
#include "sniff.h"

namespace polyaxis::io {
namespace {

using core::ErrorCode;
using core::make_error;

// A read-only mapping of a regular file, unmapped on scope exit.
class MappedFile {
 public:
  MappedFile() = default;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile() {
    if (addr_ != nullptr) munmap(addr_, size_);
  }
  core::Status open(int fd, std::size_t size, const std::string& path) {
    size_ = size;
    if (size == 0) return {};
    // MAP_POPULATE: one bulk fault instead of one per page for a file read front to back (up to
    // 1 GiB; beyond, pages come as they are read).
    const int populate = size <= (std::size_t{1} << 30) ? MAP_POPULATE : 0;
    void* addr = mmap(nullptr, size, PROT_READ, MAP_PRIVATE | populate, fd, 0);
    if (addr == MAP_FAILED) {
      return make_error(ErrorCode::kInvalidInput, fmt::format("{}: cannot map file: {}", path, std::strerror(errno)));
    }
    addr_ = addr;
    madvise(addr_, size_, MADV_SEQUENTIAL);
    return {};
  }
  std::string_view bytes() const { return addr_ ? std::string_view(static_cast<const char*>(addr_), size_) : std::string_view(); }

 private:
  void* addr_ = nullptr;
  std::size_t size_ = 0;
};

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd_ >= 0) close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

enum class Family { kStl, kObj, k3mf, kStep, kIges, kUnknown };

Family family_from_extension(const std::string& ext) {
  if (ext == ".stl") return Family::kStl;
  if (ext == ".obj") return Family::kObj;
  if (ext == ".3mf") return Family::k3mf;
  if (ext == ".step" || ext == ".stp") return Family::kStep;
  if (ext == ".iges" || ext == ".igs") return Family::kIges;
  return Family::kUnknown;
}

Family family_from_content(std::string_view data) {
  if (data.starts_with("PK\x03\x04")) return Family::k3mf;
  if (data.starts_with("ISO-10303-21")) return Family::kStep;
  const std::string_view head = data.substr(0, 4096);
  if (head.find("\nv ") != std::string_view::npos || head.starts_with("v ")) return Family::kObj;
  // IGES: 80-column records whose column 73 says S (start) on the first line.
  if (data.size() >= 80 && data[72] == 'S') return Family::kIges;
  return Family::kStl;
}

// A binary STL's triangle count is its size's (F2): one over --max-triangles is refused from the
// first 84 bytes, before the file is mapped (a 10 GB STL was read whole, 9.7 GB resident, before
// it was refused). A file that may be ASCII STL (it says "solid" and its size does not fit its
// header's count) is left to the reader.
core::Status check_binary_stl_size(int fd, std::uint64_t size, Family family, const std::string& path, const ReadOptions& options) {
  if (size < 84 || (size - 84) % 50 != 0) return {};
  std::array<char, 84> head{};
  if (::pread(fd, head.data(), head.size(), 0) != static_cast<ssize_t>(head.size())) return {};
  const std::string_view text(head.data(), head.size());
  if (family == Family::kUnknown) family = family_from_content(text);
  if (family != Family::kStl) return {};
  const std::uint64_t n = (size - 84) / 50;
  std::uint32_t declared = 0;
  std::memcpy(&declared, head.data() + 80, 4);  // little-endian hosts only, as the STL reader
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  const bool says_solid = first != std::string_view::npos && text.substr(first).size() >= 5 &&
                          std::equal(text.begin() + static_cast<std::ptrdiff_t>(first), text.begin() + static_cast<std::ptrdiff_t>(first) + 5,
                                     "solid", [](char a, char b) { return (a | 0x20) == b; });
  if (n <= options.max_triangles || (says_solid && declared != n)) return {};
  return make_error(ErrorCode::kInvalidInput, fmt::format("{}: binary STL of {} triangles (by its size, {} bytes) exceeds --max-triangles {}",
                                                          path, n, size, options.max_triangles));
}

}  // namespace

core::Result<ReadResult> read_part(const std::string& path, const ReadOptions& options) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer (F17).
  Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) {
    return make_error(ErrorCode::kInvalidInput, fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  }
  struct stat st {};
  if (fstat(fd.get(), &st) != 0) {
    return make_error(ErrorCode::kInvalidInput, fmt::format("{}: cannot stat: {}", path, std::strerror(errno)));
  }
  if (S_ISDIR(st.st_mode)) return make_error(ErrorCode::kInvalidInput, fmt::format("{}: is a directory, not a part file", path));
  if (!S_ISREG(st.st_mode)) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{}: not a regular file (FIFO, socket or device); polyaxis reads only files of known size", path));
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  // No reader needs more than ~1 kB per triangle (verbose ASCII STL is ~250 B).
  const std::uint64_t max_bytes = 84 + options.max_triangles * 1024;
  if (size > max_bytes) {
    return make_error(ErrorCode::kInvalidInput,
                      fmt::format("{}: {} bytes could hold more triangles than --max-triangles {}", path, size, options.max_triangles));
  }
  Family family = family_from_extension(lower_extension(path));
  if (family == Family::kStep || family == Family::kIges) {
    return read_cad(path, family == Family::kStep ? Format::kStep : Format::kIges, options);
  }
  if (auto s = check_binary_stl_size(fd.get(), size, family, path, options); !s) return s.error();
  MappedFile file;
  if (auto s = file.open(fd.get(), static_cast<std::size_t>(size), path); !s) return s.error();
  const std::string_view data = file.bytes();
  if (family == Family::kUnknown) family = family_from_content(data);
  switch (family) {
    case Family::kStl: return read_stl(data, path, options);
    case Family::kObj: return read_obj(data, path, options);
    case Family::k3mf: return read_3mf(data, path, options);
    case Family::kStep: return read_cad(path, Format::kStep, options);
    case Family::kIges: return read_cad(path, Format::kIges, options);
    case Family::kUnknown: break;
  }
  return make_error(ErrorCode::kInvalidInput, fmt::format("{}: unknown file format", path));
}

}  // namespace polyaxis::io
