#include "polyaxis/verify/deposit_check.h"

#include <algorithm>
#include <cmath>

#include "head_material.h"
#include "polyaxis/verify/verify.h"

namespace polyaxis::verify {

struct DepositCheck::Impl {
  detail::HeadProfile head;
  detail::MaterialIndex index;
  std::vector<std::uint32_t> before;  // material samples laid before each point
  double radius = 0.0, ignore = 0.0;
};

namespace {

// The deposit of POINTS as samples at most half a bead apart (each place once), and the count
// before each point.
// The prebuilt body (OUT's first samples) comes before them all.
std::vector<detail::MaterialSample> samples_of(const std::vector<PlannedPoint>& points, double bead_mm, std::vector<detail::MaterialSample> out,
                                               std::vector<std::uint32_t>& before) {
  before.assign(points.size(), 0);
  const double step = 0.5 * bead_mm;
  for (std::size_t i = 0; i < points.size(); ++i) {
    before[i] = static_cast<std::uint32_t>(out.size());
    if (i == 0 || !points[i].deposit) continue;
    const core::Vec3 a = points[i - 1].tip, b = points[i].tip;
    const int pieces = std::max(1, static_cast<int>(std::ceil(core::norm(b - a) / step)));
    // A bead going on from the point before has its sample there already.
    const bool goes_on = i > 1 && points[i - 1].deposit;
    for (int k = goes_on ? 1 : 0; k <= pieces; ++k) {
      const core::Vec3 p = a + (b - a) * (static_cast<double>(k) / pieces);
      const auto stamp = static_cast<std::uint32_t>(out.size());
      out.push_back({{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}, stamp, 0, 0});
    }
  }
  return out;
}

}  // namespace

DepositCheck::DepositCheck(const machine::BuildModel& model, const std::vector<PlannedPoint>& points, double bead_mm) {
  std::vector<std::uint32_t> before;
  const double radius = std::hypot(0.5 * bead_mm, 0.25 * bead_mm);
  auto samples = samples_of(points, bead_mm, detail::prebuilt_material(model.prebuilt, radius), before);
  impl_.reset(new Impl{detail::HeadProfile(model), detail::MaterialIndex(std::move(samples), kIgnorePrebuiltBeads * bead_mm), std::move(before), radius, kIgnoreBeads * bead_mm});
}

DepositCheck::~DepositCheck() = default;

bool DepositCheck::strikes(core::Vec3 tip, core::Vec3 axis, std::size_t point, double margin_mm, double turn_rad) const {
  const std::uint32_t before = point < impl_->before.size() ? impl_->before[point] : static_cast<std::uint32_t>(impl_->index.size());
  return impl_->index.deepest(impl_->head, tip, core::normalized(axis), before, impl_->radius, impl_->ignore, margin_mm, turn_rad, true).has_value();
}

}  // namespace polyaxis::verify
