// Progress of stages that can take more than a second. By default on stderr: a bar with the stage
// name, count and rate when stderr is a terminal, occasional plain lines when it is not, nothing
// when quiet. A library call that takes a ProgressCallback in its options (planner::PlanPartOptions,
// lamination::LaminateOptions, ...) sends its stages there instead, for the length of the call and
// on the calling thread only (ProgressScope): two calls on two threads each get their own.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace polyaxis::core {

enum class ProgressMode { kAuto, kQuiet };

// The command line's --quiet: applies to stages reporting on stderr (no callback in scope).
void set_progress_mode(ProgressMode mode);

// One report of a stage: DONE of TOTAL items (TOTAL 0: unknown). FINISHED on the stage's last
// report. Reports come at most a few times a second per stage, from the thread that made the
// stage's Progress or from a worker thread of the call; a callback must be thread-safe.
struct ProgressEvent {
  std::string_view stage;
  std::uint64_t done = 0;
  std::uint64_t total = 0;
  bool finished = false;
};
using ProgressCallback = std::function<void(const ProgressEvent&)>;

// While alive, every Progress made on this thread reports to CALLBACK (and not to stderr); an
// empty CALLBACK leaves the current destination in place. Scopes nest; the innermost one wins.
class ProgressScope {
 public:
  explicit ProgressScope(ProgressCallback callback);
  // The same with a callback taken from current() on another thread: a task that a call runs on a
  // worker thread reports where the call does. A null CALLBACK leaves the destination in place.
  explicit ProgressScope(std::shared_ptr<const ProgressCallback> callback);
  ~ProgressScope();

  // The callback in scope on this thread; null when stages report on stderr.
  static std::shared_ptr<const ProgressCallback> current();
  ProgressScope(const ProgressScope&) = delete;
  ProgressScope& operator=(const ProgressScope&) = delete;

 private:
  std::shared_ptr<const ProgressCallback> previous_;
  bool active_ = false;
};

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
  void send(std::uint64_t done, bool last);  // to the callback in scope at construction

  std::shared_ptr<const ProgressCallback> callback_;  // null: stderr

  std::string stage_;
  std::uint64_t total_;
  std::uint64_t done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  bool shown_ = false;
};

}  // namespace polyaxis::core
