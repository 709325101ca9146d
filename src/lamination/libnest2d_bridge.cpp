// Built as C++17 (see libnest2d_bridge.h).
#include "libnest2d_bridge.h"

#include <libnest2d/libnest2d.hpp>

namespace polyaxis::lamination::detail {

std::vector<BridgePlacement> nest_rings(const std::vector<std::vector<BridgePoint>>& rings, std::int64_t x0, std::int64_t y0,
                                        std::int64_t x1, std::int64_t y1) {
  std::vector<libnest2d::Item> items;
  items.reserve(rings.size());
  for (const auto& ring : rings) {
    ClipperLib::Path path;
    // libnest2d's clipper backend takes clockwise, closed contours.
    for (auto it = ring.rbegin(); it != ring.rend(); ++it) path.push_back({it->x, it->y});
    if (!path.empty()) path.push_back(path.front());
    items.emplace_back(path);
  }
  const libnest2d::Box bin(libnest2d::Point(x0, y0), libnest2d::Point(x1, y1));
  libnest2d::NestConfig<libnest2d::NfpPlacer, libnest2d::FirstFitSelection> config;
  config.placer_config.rotations = {libnest2d::Radians(0.0), libnest2d::Radians(libnest2d::Pi / 2), libnest2d::Radians(libnest2d::Pi),
                                    libnest2d::Radians(3 * libnest2d::Pi / 2)};
  config.placer_config.alignment = libnest2d::NfpPlacer::Config::Alignment::DONT_ALIGN;
  config.placer_config.parallel = false;
  config.placer_config.accuracy = 0.2f;
  libnest2d::nest(items, bin, 0, config);
  std::vector<BridgePlacement> out;
  out.reserve(items.size());
  for (const auto& item : items) {
    BridgePlacement p;
    p.bin = item.binId();
    const libnest2d::Radians turn = item.rotation();
    p.rotation_rad = turn.operator double();
    p.dx = libnest2d::getX(item.translation());
    p.dy = libnest2d::getY(item.translation());
    out.push_back(p);
  }
  return out;
}

}  // namespace polyaxis::lamination::detail
