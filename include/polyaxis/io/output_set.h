// A command's output files as one set (RELIABILITY O5, O9): a plan's G-code, plan.json,
// report.json and report.html must never be a mix of two runs, nor a failed run's files under
// their final names.
//
// The files are written into a hidden run directory inside the output directory
// (`.polyaxis-run-<pid>-<n>`), then, under an exclusive lock on `<dir>/.polyaxis.lock`, moved to
// their final names in the order they were added (the caller adds the machine program last).
// Before the first move every final name is checked: one that exists and is not a regular file
// (a directory, a FIFO, a device) fails the whole set with nothing moved. A set that is not
// committed (an error, an exception) removes its run directory; one killed outright leaves it,
// and the next set opened in that directory removes every run directory whose process is gone,
// and the `.NAME.tmp-XXXXXX` files of write_file_atomic older than an hour.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "polyaxis/core/result.h"
#include "polyaxis/io/write_file.h"

namespace polyaxis::io {

class OutputSet {
 public:
  // Creates DIR (and its parents) and the run directory, after removing stale ones. kOutput on
  // failure.
  static core::Result<OutputSet> open(const std::string& dir);
  OutputSet(OutputSet&& other) noexcept;
  OutputSet& operator=(OutputSet&&) = delete;
  OutputSet(const OutputSet&) = delete;
  ~OutputSet();

  // Writes NAME (a plain file name) into the run directory; kSynced fsyncs it.
  core::Status add(const std::string& name, std::string_view bytes, Durability durability = Durability::kAtomic);
  // Moves every added file to DIR/NAME, under the lock, in the order added. kOutput naming the
  // file when a final name cannot take it (nothing moved) or a move fails.
  core::Status commit();

  const std::string& dir() const { return dir_; }

 private:
  OutputSet(std::string dir, std::string run_dir) : dir_(std::move(dir)), run_dir_(std::move(run_dir)) {}
  std::string dir_, run_dir_;
  std::vector<std::string> names_;
  bool done_ = false;
};

}  // namespace polyaxis::io
