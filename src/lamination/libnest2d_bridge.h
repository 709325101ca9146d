// The one call into libnest2d, behind plain types: libnest2d 5.0's headers compile as C++17 only
// (its Radians comparison is ambiguous under C++20), so libnest2d_bridge.cpp is built as C++17 and
// includes nothing of ours but this header.
#pragma once

#include <cstdint>
#include <vector>

namespace polyaxis::lamination::detail {

struct BridgePoint {
  std::int64_t x = 0, y = 0;
};

struct BridgePlacement {
  int bin = -1;               // -1: placed nowhere
  double rotation_rad = 0.0;  // the item's turn about the origin of its own coordinates ...
  std::int64_t dx = 0, dy = 0;  // ... then this translation
};

// Nests the closed counter-clockwise RINGS into bins [x0, x1] × [y0, y1] (integer units), turning
// them by multiples of 90°, with no gap between items (the caller grows them). One placement per ring.
std::vector<BridgePlacement> nest_rings(const std::vector<std::vector<BridgePoint>>& rings, std::int64_t x0, std::int64_t y0,
                                        std::int64_t x1, std::int64_t y1);

}  // namespace polyaxis::lamination::detail
