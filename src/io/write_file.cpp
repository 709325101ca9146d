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

core::Status write_file_atomic(const std::string& path, std::string_view bytes, Durability durability) {
  const std::filesystem::path target(path);
  // A FIFO, a device or a directory at PATH is not replaced by a regular file (O5).
  if (struct stat st {}; ::lstat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: exists and is not a regular file; not replaced", path));
  }
  std::string tmpl = (target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path()).string() + "/." +
                     target.filename().string() + ".tmp-XXXXXX";
  const int fd = mkostemp(tmpl.data(), O_CLOEXEC);
  auto fail = [&](const char* what) {
    const std::string reason = std::strerror(errno);
    return core::make_error(core::ErrorCode::kOutput, fmt::format("{}: cannot {}: {}", path, what, reason));
  };
  if (fd < 0) return fail("create a temporary file");
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      auto e = fail("write");
      ::close(fd);
      ::unlink(tmpl.c_str());
      return e;
    }
    written += static_cast<std::size_t>(n);
  }
  if (durability == Durability::kSynced && ::fsync(fd) != 0) {
    auto e = fail("sync");
    ::close(fd);
    ::unlink(tmpl.c_str());
    return e;
  }
  ::fchmod(fd, 0644);  // mkostemp makes 0600; outputs are ordinary files
  if (::close(fd) != 0) {
    auto e = fail("close");
    ::unlink(tmpl.c_str());
    return e;
  }
  if (std::rename(tmpl.c_str(), path.c_str()) != 0) {
    auto e = fail("rename the temporary file");
    ::unlink(tmpl.c_str());
    return e;
  }
  return {};
}

}  // namespace polyaxis::io
