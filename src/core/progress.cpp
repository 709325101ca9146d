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

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

}  // namespace

void set_progress_mode(ProgressMode mode) { g_mode = mode; }

Progress::Progress(std::string stage, std::uint64_t total)
    : stage_(std::move(stage)), total_(total), start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

Progress::~Progress() {
  if (shown_) {
    draw(total_ ? total_ : done_, true);
    if (stderr_is_terminal()) std::fputc('\n', stderr);
  }
}

void Progress::update(std::uint64_t done) { draw(done, false); }

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
