#include "unwind.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace polyaxis::planner::detail {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double tilt_deg(core::Vec3 axis) { return std::atan2(std::hypot(axis.x, axis.y), axis.z) / kDeg; }

// The turn (degrees, in (−180, 180]) from azimuth A to azimuth B.
double wrapped(double a, double b) {
  double d = std::remainder(b - a, 360.0);
  if (d <= -180.0) d += 360.0;
  return d;
}

}  // namespace

std::vector<post::ProgramPoint> insert_c_unwinds(const std::vector<post::ProgramPoint>& program,
                                                 const std::vector<slicing::Layer>& layers, const machine::MachineConfig& machine) {
  if (!machine::unwinds_c(machine)) return program;
  // The tool axis's azimuth about the vertical, unwrapped along the program (held where upright).
  std::vector<double> azimuth(program.size(), 0.0);
  std::optional<double> last;
  double unwrapped = 0.0;
  for (std::size_t i = 0; i < program.size(); ++i) {
    const core::Vec3 axis = core::normalized(program[i].tool_axis_part);
    if (tilt_deg(axis) >= kWindingTiltDeg) {
      const double a = std::atan2(axis.y, axis.x) / kDeg;
      unwrapped = last ? unwrapped + wrapped(*last, a) : a;
      last = a;
    }
    azimuth[i] = unwrapped;
  }
  std::vector<post::ProgramPoint> out;
  out.reserve(program.size());
  double lo = azimuth.empty() ? 0.0 : azimuth[0], hi = lo;  // the azimuth's range since the last unwind
  for (std::size_t i = 0; i < program.size(); ++i) {
    const post::ProgramPoint& pt = program[i];
    out.push_back(pt);
    // The coming bead: up to the next point reached with the process off.
    std::size_t j = i + 1;
    double next_lo = std::min(lo, azimuth[i]), next_hi = std::max(hi, azimuth[i]);
    while (j < program.size() && program[j].process_on) next_lo = std::min(next_lo, azimuth[j]), next_hi = std::max(next_hi, azimuth[j]), ++j;
    const core::Vec3 axis = core::normalized(pt.tool_axis_part);
    const bool eligible = !pt.process_on && i > 0 && tilt_deg(axis) <= kUnwindMaxTurnDeg &&
                          (pt.layer >= layers.size() || tilt_deg(layers[pt.layer].frame.d) <= kUnwindMaxLeanDeg);
    if (eligible && next_hi - next_lo >= kUnwindAfterDeg) {
      post::ProgramPoint up = pt;
      up.tool_axis_part = {0.0, 0.0, 1.0};
      up.c_unwind = true;
      up.comment_if_new_block = "unwind C";
      out.push_back(up);
      if (j > i + 1) {  // a bead follows: it starts with its own axis
        post::ProgramPoint back = pt;
        back.comment_if_new_block.clear();
        out.push_back(back);
      }
      lo = hi = azimuth[i];
    }
    for (std::size_t k = i; k < j; ++k) lo = std::min(lo, azimuth[k]), hi = std::max(hi, azimuth[k]);
    for (std::size_t k = i + 1; k < j; ++k) out.push_back(program[k]);
    i = j - 1;
  }
  return out;
}

}  // namespace polyaxis::planner::detail
