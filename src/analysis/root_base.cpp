#include "polyaxis/analysis/root_base.h"

#include <fmt/format.h>

#include <cmath>
#include <sstream>
#include <vector>

namespace polyaxis::analysis {

core::Result<RootBase> parse_root_base(const std::string& text) {
  RootBase base;
  if (text.empty()) return base;
  if (text == "z-min") {
    base.kind = RootBase::Kind::kLowest;
    return base;
  }
  auto bad = [&](const std::string& why) {
    return core::make_error(core::ErrorCode::kUsage,
                            fmt::format("--root-base: '{}' {}; expected z-min, a face id or PX,PY,PZ,NX,NY,NZ", text, why));
  };
  std::vector<double> numbers;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    try {
      std::size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(v)) return bad("has a part that is not a finite number");
      numbers.push_back(v);
    } catch (const std::exception&) {
      return bad("has a part that is not a number");
    }
  }
  if (numbers.size() == 1) {
    if (numbers[0] < 0 || numbers[0] != std::floor(numbers[0]) || numbers[0] > 4e9) return bad("is not a face id");
    base.kind = RootBase::Kind::kFace;
    base.face = static_cast<std::uint32_t>(numbers[0]);
    return base;
  }
  if (numbers.size() != 6) return bad("is neither one number nor six");
  base.kind = RootBase::Kind::kPlane;
  base.point = {numbers[0], numbers[1], numbers[2]};
  base.normal = {numbers[3], numbers[4], numbers[5]};
  if (core::norm(base.normal) < 1e-12) return bad("has a zero normal");
  return base;
}

}  // namespace polyaxis::analysis
