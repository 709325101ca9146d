// The head's clearance at one program point (verify.h clearance_at), for `polyaxis explain`.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "head_material.h"
#include "polyaxis/verify/verify.h"

namespace polyaxis::verify {

PointClearance clearance_at(const machine::BuildModel& model, const std::vector<post::ProgramPoint>& program, std::size_t point,
                            double bead_mm) {
  PointClearance out;
  const post::ProgramPoint& at = program.at(point);
  const core::Vec3 tip = at.tip_part_mm, axis = core::normalized(at.tool_axis_part);
  out.fixture_mm = std::min(machine::head_clearance_mm(model, tip, axis), machine::tip_clearance_mm(model, tip));
  const detail::HeadProfile head(model);
  // The beads as balls at most half a bead apart, of the radius that covers the bead between them
  // (verify.cpp's material samples).
  const double step = 0.5 * bead_mm, radius = std::hypot(0.5 * bead_mm, 0.5 * step), ignore = kIgnoreBeads * bead_mm;
  auto consider = [&](core::Vec3 q, const post::ProgramPoint& p) {
    if (core::norm(q - tip) <= ignore) return;
    const double d = head.distance(q - tip, axis) - radius;
    if (!out.deposit_mm || d < *out.deposit_mm) {
      out.deposit_mm = d, out.deposit_point = q, out.deposit_body = fmt::format("deposit of layer {} region {}", p.layer, p.region);
      out.deposit_layer = p.layer, out.deposit_region = p.region;
    }
  };
  for (const detail::MaterialSample& s : detail::prebuilt_material(model.prebuilt, radius)) {
    const core::Vec3 q{s.position[0], s.position[1], s.position[2]};
    if (core::norm(q - tip) <= kIgnorePrebuiltBeads * bead_mm) continue;
    const double d = head.distance(q - tip, axis) - radius;
    if (!out.deposit_mm || d < *out.deposit_mm) out.deposit_mm = d, out.deposit_point = q, out.deposit_body = kPrebuiltBody;
  }
  for (std::size_t i = 1; i < point; ++i) {
    const post::ProgramPoint& a = program[i - 1];
    const post::ProgramPoint& b = program[i];
    if (!b.process_on) continue;
    const double length = core::norm(b.tip_part_mm - a.tip_part_mm);
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / step)));
    for (int k = 0; k <= pieces; ++k) consider(a.tip_part_mm + (b.tip_part_mm - a.tip_part_mm) * (static_cast<double>(k) / pieces), b);
  }
  return out;
}

}  // namespace polyaxis::verify
