// The head against the deposit of a planned sequence of points, for the planner's own choices
// before any G-code exists (torch tilts that keep clear, travel that goes around): the same head
// model, material samples and ignored zone as verify_build (verify.h), over the plan's points
// rather than the program read back. The read-back verification still judges the result.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/machine/build_model.h"

namespace polyaxis::verify {

// A planned point: the tip, and whether the move that reaches it deposits.
struct PlannedPoint {
  core::Vec3 tip;
  bool deposit = false;
};

class DepositCheck {
 public:
  // POINTS in build order; the deposit is every move into a point with `deposit`, sampled at most
  // half a bead apart. Cost: O(n log n) in the samples.
  DepositCheck(const machine::BuildModel& model, const std::vector<PlannedPoint>& points, double bead_mm);
  ~DepositCheck();
  DepositCheck(const DepositCheck&) = delete;
  DepositCheck& operator=(const DepositCheck&) = delete;

  // True when the head at (TIP, AXIS) comes within MARGIN_MM (plus TURN_RAD times a head point's
  // distance from the tip) of the deposit laid by the moves into the points before POINT (the
  // material within kIgnoreBeads of the tip left out). With the margin a move's length and the turn
  // its axis's, false clears the whole move into (TIP, AXIS).
  bool strikes(core::Vec3 tip, core::Vec3 axis, std::size_t point, double margin_mm, double turn_rad = 0.0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyaxis::verify
