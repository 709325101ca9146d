// Writing output files so that a failure never leaves a partial file (RELIABILITY O5).
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"

namespace polyaxis::io {

enum class Durability {
  kSynced,  // fsync before the rename: the file survives a power cut (machine code)
  kAtomic,  // rename only: readers and failures never see a partial file (reports, layers)
};

// Writes BYTES to a temporary file beside PATH and renames it over PATH (after an fsync when
// kSynced). On any failure the temporary file is removed and PATH is untouched: Error kOutput
// naming the path. An existing PATH that is not a regular file (a FIFO, a device, a directory)
// is refused, not replaced.
core::Status write_file_atomic(const std::string& path, std::string_view bytes, Durability durability = Durability::kSynced);

// The same for bytes made piece by piece (written as they come, while the rest is being made): a
// temporary file beside PATH, renamed over PATH by commit(), removed when dropped uncommitted.
// Errors are kOutput naming PATH; after one, write() and commit() fail again and change nothing.
class AtomicFile {
 public:
  // Refuses an existing PATH that is not a regular file, as write_file_atomic does.
  static core::Result<AtomicFile> create(const std::string& path);
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&&) = delete;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  core::Status write(std::string_view bytes);
  core::Status commit(Durability durability = Durability::kSynced);

 private:
  AtomicFile(std::string path, std::string temporary, int fd) : path_(std::move(path)), temporary_(std::move(temporary)), fd_(fd) {}
  core::Error fail(const char* what);  // removes the temporary file
  std::string path_, temporary_;
  int fd_ = -1;  // -1 once committed or failed
};

}  // namespace polyaxis::io
