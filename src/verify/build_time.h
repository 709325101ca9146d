// The build time of a program as LinuxCNC 2.9's trajectory planner runs it (src/emc/tp/tp.c,
// emccanon.cc), move by move: each block's velocity and acceleration are the largest its axes allow
// (the slowest axis decides, as emccanon's getStraightVelocity/-Acceleration); a block lasts at
// least one servo period; blocks with rotary motion blend parabolically (each plans to stop at its
// end with half the acceleration, and the next starts while it slows below the blend velocity,
// itself bounded by G64 P); blocks without rotary motion blend tangentially or through a circular
// arc within G64 P, with velocities planned over the whole chain; dwells stop the motion.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/machine/machine.h"
#include "polyaxis/verify/simulate.h"

namespace polyaxis::verify::detail {

// LinuxCNC's default servo period (the sim configurations' BASE/SERVO_PERIOD).
inline constexpr double kServoPeriodS = 0.001;

// One block as the estimate needs it: the joints' displacement and the requested feed.
struct TimedBlock {
  double d[5] = {0, 0, 0, 0, 0};  // |Δ| of X, Y, Z (mm), tilt, C (degrees)
  double u_xyz[3] = {0, 0, 0};    // the XYZ direction (unit; zeros for a rotary-only block)
  bool rapid = false;
  double feed_per_min = 0.0;      // G94 F: mm/min, or deg/min for a rotary-only block
  double inverse_time_min = 0.0;  // G93: the block's time, min (0: not inverse time)
  BuildTimePart part = BuildTimePart::kTravel;
};

struct WalkMove;

// MV as the estimate takes it: the joints' travel (the TCP's path on a robot cell, whose arm the
// estimate does not model), the feed the block asks for, and its part of the build time.
TimedBlock timed_block(const WalkMove& mv);

class BuildTimer {
 public:
  // KEEP_DURATIONS: keep each block's own time (durations()), for a clock along the program.
  explicit BuildTimer(const machine::MachineConfig& machine, bool keep_durations = false);
  // A move of the program from a known pose: a change of the process state stops the motion first
  // (LinuxCNC waits for the motion before it switches an output, M64/M65), then the block.
  void move(const WalkMove& mv);
  void block(const TimedBlock& b);
  void dwell(double seconds);  // stops the motion
  // The estimate of everything added so far.
  BuildTime finish();
  // With KEEP_DURATIONS, after finish(): the time of each block()/move() call in call order (a
  // parabolic blend's overlap counted in the block that ends with it; 0 for a block that moves
  // nothing). Dwells are not in it.
  const std::vector<double>& durations() const { return durations_; }

 private:
  // A block in the planner's units: mm along XYZ, or degrees for a rotary-only block.
  struct Segment {
    double length = 0.0;
    double vmax = 0.0;   // the requested feed, the axes' velocities and one servo period
    double accel = 0.0;  // the axes' accelerations (emccanon's slowest axis)
    bool rotary = false;
    double u[3] = {0, 0, 0};
    BuildTimePart part = BuildTimePart::kTravel;
    std::size_t slot = 0;  // its entry in durations_ (when kept)
  };
  void flush();  // times the chain of blocks since the last stop

  machine::MachineConfig m_;
  bool keep_durations_ = false;
  bool last_on_ = false;  // the process state of the last move
  std::vector<Segment> chain_;
  std::vector<double> durations_;
  BuildTime time_;
};

}  // namespace polyaxis::verify::detail
