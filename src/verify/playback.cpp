#include "polyaxis/verify/playback.h"

#include <algorithm>

#include "build_time.h"
#include "gcode_walk.h"

namespace polyaxis::verify {

core::Result<std::vector<PlaybackFrame>> playback_frames(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                                         std::string_view gcode) {
  std::vector<PlaybackFrame> frames;
  // Each frame's own time, known once the estimate has timed the whole chain it blends in: a
  // block's index in the timer's durations, or a dwell's seconds.
  struct Step {
    bool block = false;
    std::size_t index = 0;
    double seconds = 0.0;
  };
  std::vector<Step> steps;
  detail::BuildTimer timer(machine, true);
  machine::MachinePose at{};
  std::int64_t layer = -1, region = -1;
  bool has_arm = false;
  std::array<float, 6> arm{};
  detail::WalkCallbacks cb;
  cb.move = [&](const detail::WalkMove& mv) {
    if (mv.from_known) {
      timer.move(mv);
      steps.push_back({true, timer.durations().size() - 1, 0.0});
    } else {
      steps.push_back({});
    }
    at = mv.to, layer = mv.layer, region = mv.region;
    if (mv.arm_to) {
      has_arm = true;
      for (std::size_t k = 0; k < 6; ++k) arm[k] = static_cast<float>((*mv.arm_to)[k]);
    }
    frames.push_back({mv.to, 0.0, mv.line, mv.process_on, mv.rapid, mv.layer, mv.region, has_arm, arm});
  };
  cb.dwell = [&](std::uint64_t line, double seconds, bool on) {
    timer.dwell(seconds);
    if (frames.empty()) return;
    frames.push_back({at, 0.0, line, on, false, layer, region, has_arm, arm});
    steps.push_back({false, 0, std::max(0.0, seconds)});
  };
  bool end = false;
  if (auto st = detail::walk_gcode(machine, gcode, &process, cb, &end); !st) return st.error();
  timer.finish();
  double now = 0.0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    now += steps[i].block ? timer.durations()[steps[i].index] : steps[i].seconds;
    frames[i].time_s = now;
  }
  return frames;
}

}  // namespace polyaxis::verify
