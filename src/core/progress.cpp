#include "polyaxis/core/progress.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>

namespace polyaxis::core {
namespace {

std::atomic<ProgressMode> g_mode{ProgressMode::kAuto};

constexpr auto kFirstShow = std::chrono::seconds(1);
constexpr auto kTerminalRedraw = std::chrono::milliseconds(200);
constexpr auto kPlainRedraw = std::chrono::seconds(5);

constexpr auto kCallbackInterval = std::chrono::milliseconds(200);

// The callback of the innermost ProgressScope on this thread.
thread_local std::shared_ptr<const ProgressCallback> t_callback;

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

}  // namespace

void set_progress_mode(ProgressMode mode) { g_mode = mode; }

ProgressScope::ProgressScope(ProgressCallback callback) {
  if (!callback) return;
  active_ = true;
  previous_ = std::move(t_callback);
  t_callback = std::make_shared<const ProgressCallback>(std::move(callback));
}

ProgressScope::ProgressScope(std::shared_ptr<const ProgressCallback> callback) {
  if (!callback) return;
  active_ = true;
  previous_ = std::move(t_callback);
  t_callback = std::move(callback);
}

std::shared_ptr<const ProgressCallback> ProgressScope::current() { return t_callback; }

ProgressScope::~ProgressScope() {
  if (active_) t_callback = std::move(previous_);
}

Progress::Progress(std::string stage, std::uint64_t total)
    : callback_(t_callback), stage_(std::move(stage)), total_(total), start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

Progress::~Progress() {
  if (callback_) {
    send(total_ ? total_ : done_, true);
    return;
  }
  if (shown_) {
    draw(total_ ? total_ : done_, true);
    if (stderr_is_terminal()) std::fputc('\n', stderr);
  }
}

void Progress::update(std::uint64_t done) {
  if (callback_) {
    send(done, false);
  } else {
    draw(done, false);
  }
}

void Progress::send(std::uint64_t done, bool last) {
  done_ = done;
  const auto now = std::chrono::steady_clock::now();
  // A callback hears every stage from its start, at most every kCallbackInterval, and its end.
  if (shown_ && !last && now - last_draw_ < kCallbackInterval) return;
  shown_ = true;
  last_draw_ = now;
  (*callback_)(ProgressEvent{stage_, done, total_, last});
}

void Progress::draw(std::uint64_t done, bool last) {
  done_ = done;
  if (g_mode == ProgressMode::kQuiet) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < kFirstShow) return;
  const bool tty = stderr_is_terminal();
  if (shown_ && now - last_draw_ < (tty ? kTerminalRedraw : kPlainRedraw) && done != total_ && !last) return;
  shown_ = true;
  last_draw_ = now;
  const double secs = std::chrono::duration<double>(now - start_).count();
  const double rate = secs > 0 ? static_cast<double>(done) / secs : 0.0;
  if (total_ == 0) {  // unknown total: the count and the rate
    if (tty) {
      std::fprintf(stderr, "\r%-12s %llu  %.3g/s", stage_.c_str(), static_cast<unsigned long long>(done), rate);
    } else {
      std::fprintf(stderr, "%s: %llu (%.3g/s)\n", stage_.c_str(), static_cast<unsigned long long>(done), rate);
    }
  } else if (tty) {
    constexpr int kWidth = 30;
    const int filled = total_ ? static_cast<int>(kWidth * static_cast<double>(done) / static_cast<double>(total_)) : 0;
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%-12s [%s] %llu/%llu  %.3g/s", stage_.c_str(), bar.c_str(),
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), rate);
  } else {
    std::fprintf(stderr, "%s: %llu/%llu (%.3g/s)\n", stage_.c_str(), static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(total_), rate);
  }
  std::fflush(stderr);
}

}  // namespace polyaxis::core
