#include "polyaxis/verify/playback.h"

#include <algorithm>

#include "gcode_walk.h"

namespace polyaxis::verify {

core::Result<std::vector<PlaybackFrame>> playback_frames(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                                         std::string_view gcode) {
  std::vector<PlaybackFrame> frames;
  double now = 0.0;
  machine::MachinePose at{};
  std::int64_t layer = -1, region = -1;
  bool has_arm = false;
  std::array<float, 6> arm{};
  detail::WalkCallbacks cb;
  cb.move = [&](const detail::WalkMove& mv) {
    double minutes = mv.time_min;
    if (mv.from_known && (mv.rapid || minutes <= 0.0)) {
      const double linear = mv.l_xyz_mm / machine.feed.linear_max_mm_min;
      const double rotary = std::max(mv.d_tilt_deg, mv.d_c_deg) / machine.feed.rotary_max_deg_min;
      minutes = std::max(linear, rotary);
    }
    if (mv.from_known) now += 60.0 * std::max(0.0, minutes);
    at = mv.to, layer = mv.layer, region = mv.region;
    if (mv.arm_to) {
      has_arm = true;
      for (std::size_t k = 0; k < 6; ++k) arm[k] = static_cast<float>((*mv.arm_to)[k]);
    }
    frames.push_back({mv.to, now, mv.line, mv.process_on, mv.rapid, mv.layer, mv.region, has_arm, arm});
  };
  cb.dwell = [&](std::uint64_t line, double seconds, bool on) {
    now += std::max(0.0, seconds);
    if (!frames.empty()) frames.push_back({at, now, line, on, false, layer, region, has_arm, arm});
  };
  bool end = false;
  if (auto st = detail::walk_gcode(machine, gcode, &process, cb, &end); !st) return st.error();
  return frames;
}

}  // namespace polyaxis::verify
