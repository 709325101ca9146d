// Progress on stderr for stages that can take more than a second: a bar with the stage name,
// count and rate when stderr is a terminal, occasional plain lines when it is not, nothing when quiet.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace polyaxis::core {

enum class ProgressMode { kAuto, kQuiet };

void set_progress_mode(ProgressMode mode);

class Progress {
 public:
  // total may be 0 when unknown: then the count and rate are shown without a bar. Nothing is
  // shown for a stage that ends within a second.
  Progress(std::string stage, std::uint64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(std::uint64_t done);  // cheap: redraws at most a few times a second

 private:
  void draw(std::uint64_t done, bool last);  // LAST: the stage's end, always drawn once shown

  std::string stage_;
  std::uint64_t total_;
  std::uint64_t done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  bool shown_ = false;
};

}  // namespace polyaxis::core
