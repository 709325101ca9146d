// Shares bit-identical points while a reader streams them in (STL has no indices). Exact only:
// merging within a tolerance is the repair pass's job. -0.0 and +0.0 are the same point (T9).
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/core/vec3.h"

namespace polyaxis::io {

class PointWelder {
 public:
  // expected_points: a capacity hint (e.g. half the triangle count for a closed mesh).
  PointWelder(std::vector<core::Vec3>& points, std::size_t expected_points);

  // Index of P in points, appending it if new. P must be finite. Amortised O(1).
  std::uint32_t index_of(core::Vec3 p);

 private:
  void grow();

  std::vector<core::Vec3>& points_;
  std::vector<std::uint32_t> slots_;  // open addressing, linear probing; kEmpty marks a free slot
  std::uint64_t mask_ = 0;
  // Direct-mapped cache of recently seen points: neighbouring facets of a file share corners, so
  // most repeats are found here without touching the large table.
  static constexpr std::size_t kRecent = 4096;
  std::uint32_t recent_[kRecent];
};

}  // namespace polyaxis::io

namespace polyaxis::io {

// The same for points that are exactly single-precision (binary STL): the key lives in the slot
// itself (16 bytes), so a lookup touches one cache line instead of a slot and a point.
class FloatPointWelder {
 public:
  FloatPointWelder(std::vector<core::Vec3>& points, std::size_t expected_points);
  std::uint32_t index_of(float x, float y, float z);
  // Index of the point if it is already there, else kAbsent. Read-only: safe from several threads.
  static constexpr std::uint32_t kAbsent = 0xffffffffu;
  std::uint32_t find(float x, float y, float z) const;

 private:
  struct Slot {
    float x, y, z;
    std::uint32_t index;  // kEmpty marks a free slot
  };
  void grow();

  std::vector<core::Vec3>& points_;
  std::vector<Slot> slots_;
  std::uint64_t mask_ = 0;
  // Direct-mapped cache of recently seen points (64 KiB, in L2): a vertex's facets are mostly near
  // each other in a file, so most repeats are found here without a miss in the large table.
  static constexpr std::size_t kRecent = 4096;
  std::vector<Slot> recent_;
};

}  // namespace polyaxis::io
