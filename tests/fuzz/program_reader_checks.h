// The invariants of a program reader's fuzz target (fuzz_gcode, fuzz_toolpath_3mf): PROGRAM on
// machine M is read or refused with kInvalidInput, or kMachineLimit for a pose no axis reaches,
// never a signal; the playback reads it exactly when simulate does, with finite poses and a clock
// that never runs backwards.
#pragma once

#include <cmath>
#include <string_view>

#include "fuzz_require.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"
#include "polyaxis/verify/playback.h"
#include "polyaxis/verify/simulate.h"

namespace polyaxis::fuzz {

inline void check_program_reader(const machine::MachineConfig& m, const process::ProcessConfig& p, std::string_view program) {
  auto sim = verify::simulate(m, program, {}, &p);
  if (!sim) {
    require(sim.error().code == core::ErrorCode::kInvalidInput || sim.error().code == core::ErrorCode::kMachineLimit);
  } else {
    require(std::isfinite(sim.value().path_length_mm) && sim.value().path_length_mm >= 0.0);
  }
  auto frames = verify::playback_frames(m, p, program);
  require(frames.ok() == sim.ok());
  if (!frames) return;
  double last = 0.0;
  for (const auto& f : frames.value()) {
    require(std::isfinite(f.pose.x_mm) && std::isfinite(f.pose.y_mm) && std::isfinite(f.pose.z_mm) && std::isfinite(f.pose.a_or_b_deg) &&
            std::isfinite(f.pose.c_deg));
    require(std::isfinite(f.time_s) && f.time_s >= last);
    last = f.time_s;
  }
}

}  // namespace polyaxis::fuzz
