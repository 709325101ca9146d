#include "polyaxis/io/write_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace polyaxis::io {

core::Result<AtomicFile> AtomicFile::create(const std::string& path) {
  const std::filesystem::path target(path);
  // A FIFO, a device or a directory at PATH is not replaced by a regular file (O5).
  if (struct stat st {}; ::lstat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: exists and is not a regular file; not replaced", path));
  }
  std::string tmpl = (target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path()).string() + "/." +
                     target.filename().string() + ".tmp-XXXXXX";
  const int fd = mkostemp(tmpl.data(), O_CLOEXEC);
  if (fd < 0) {
    const std::string reason = std::strerror(errno);
    return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot create a temporary file: {}", path, reason));
  }
  return AtomicFile(path, std::move(tmpl), fd);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept : path_(std::move(other.path_)), temporary_(std::move(other.temporary_)), fd_(other.fd_) {
  other.fd_ = -1;
}

AtomicFile::~AtomicFile() {
  if (fd_ < 0) return;
  ::close(fd_);
  ::unlink(temporary_.c_str());
}

core::Error AtomicFile::fail(const char* what) {
  const std::string reason = std::strerror(errno);
  if (fd_ >= 0) ::close(fd_);
  ::unlink(temporary_.c_str());
  fd_ = -1;
  return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot {}: {}", path_, what, reason));
}

core::Status AtomicFile::write(std::string_view bytes) {
  if (fd_ < 0) return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot write: the file was closed", path_));
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail("write");
    }
    written += static_cast<std::size_t>(n);
  }
  return {};
}

core::Status AtomicFile::commit(Durability durability) {
  if (fd_ < 0) return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot commit: the file was closed", path_));
  if (durability == Durability::kSynced && ::fsync(fd_) != 0) return fail("sync");
  ::fchmod(fd_, 0644);  // mkostemp makes 0600; outputs are ordinary files
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) return fail("close");
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) return fail("rename the temporary file");
  return {};
}

core::Status write_file_atomic(const std::string& path, std::string_view bytes, Durability durability) {
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (auto s = file.value().write(bytes); !s) return s;
  return file.value().commit(durability);
}

}  // namespace polyaxis::io
