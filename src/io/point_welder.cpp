#include "point_welder.h"

#include <algorithm>
#include <bit>
#include <iterator>
#include <cstring>

namespace polyaxis::io {
namespace {

constexpr std::uint32_t kEmpty = 0xffffffffu;

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v + 0.0); }  // -0 + 0 = +0

std::uint64_t mix(std::uint64_t h) {  // murmur3 finaliser
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h;
}

// One finaliser over a multiply-combined key: the coordinates' bits are already well spread.
std::uint64_t hash_point(core::Vec3 p) {
  return mix(bits(p.x) * 0x9E3779B97F4A7C15ULL ^ bits(p.y) * 0xC2B2AE3D27D4EB4FULL ^ bits(p.z));
}

}  // namespace

PointWelder::PointWelder(std::vector<core::Vec3>& points, std::size_t expected_points) : points_(points) {
  std::fill(std::begin(recent_), std::end(recent_), kEmpty);
  std::size_t capacity = 1024;
  while (capacity < 2 * expected_points) capacity *= 2;
  slots_.assign(capacity, kEmpty);
  mask_ = capacity - 1;
  for (std::uint32_t i = 0; i < points_.size(); ++i) {
    std::uint64_t s = hash_point(points_[i]) & mask_;
    while (slots_[s] != kEmpty) s = (s + 1) & mask_;
    slots_[s] = i;
  }
}

std::uint32_t PointWelder::index_of(core::Vec3 p) {
  p = {p.x + 0.0, p.y + 0.0, p.z + 0.0};
  const std::uint64_t h = hash_point(p);
  std::uint32_t& cached = recent_[(h >> 40) % kRecent];
  if (cached != kEmpty && points_[cached] == p) return cached;
  std::uint64_t s = h & mask_;
  while (true) {
    const std::uint32_t i = slots_[s];
    if (i == kEmpty) break;
    if (points_[i] == p) return cached = i;
    s = (s + 1) & mask_;
  }
  const auto index = static_cast<std::uint32_t>(points_.size());
  points_.push_back(p);
  slots_[s] = index;
  if (2 * points_.size() > slots_.size()) grow();
  return cached = index;
}

void PointWelder::grow() {
  slots_.assign(slots_.size() * 2, kEmpty);
  mask_ = slots_.size() - 1;
  for (std::uint32_t i = 0; i < points_.size(); ++i) {
    std::uint64_t s = hash_point(points_[i]) & mask_;
    while (slots_[s] != kEmpty) s = (s + 1) & mask_;
    slots_[s] = i;
  }
}

}  // namespace polyaxis::io

namespace polyaxis::io {
namespace {

std::uint64_t hash_float_point(float x, float y, float z) {
  const auto bx = std::bit_cast<std::uint32_t>(x), by = std::bit_cast<std::uint32_t>(y), bz = std::bit_cast<std::uint32_t>(z);
  return mix((static_cast<std::uint64_t>(bx) << 32 | by) * 0x9E3779B97F4A7C15ULL ^ bz);
}

}  // namespace

FloatPointWelder::FloatPointWelder(std::vector<core::Vec3>& points, std::size_t expected_points) : points_(points) {
  std::size_t capacity = 1024;
  while (capacity < 2 * expected_points) capacity *= 2;
  slots_.assign(capacity, Slot{0, 0, 0, kEmpty});
  mask_ = capacity - 1;
  recent_.assign(kRecent, Slot{0, 0, 0, kEmpty});
}

std::uint32_t FloatPointWelder::index_of(float x, float y, float z) {
  x += 0.0f;  // -0 + 0 = +0 (T9)
  y += 0.0f;
  z += 0.0f;
  const std::uint64_t h = hash_float_point(x, y, z);
  Slot& cached = recent_[(h >> 40) % kRecent];
  if (cached.index != kEmpty && cached.x == x && cached.y == y && cached.z == z) return cached.index;
  std::uint64_t s = h & mask_;
  while (true) {
    const Slot& slot = slots_[s];
    if (slot.index == kEmpty) break;
    if (slot.x == x && slot.y == y && slot.z == z) {
      cached = slot;
      return slot.index;
    }
    s = (s + 1) & mask_;
  }
  const auto index = static_cast<std::uint32_t>(points_.size());
  points_.push_back({x, y, z});
  slots_[s] = cached = Slot{x, y, z, index};
  if (2 * points_.size() > slots_.size()) grow();
  return index;
}

std::uint32_t FloatPointWelder::find(float x, float y, float z) const {
  x += 0.0f;
  y += 0.0f;
  z += 0.0f;
  for (std::uint64_t s = hash_float_point(x, y, z) & mask_;; s = (s + 1) & mask_) {
    const Slot& slot = slots_[s];
    if (slot.index == kEmpty) return kAbsent;
    if (slot.x == x && slot.y == y && slot.z == z) return slot.index;
  }
}

void FloatPointWelder::grow() {
  std::vector<Slot> old(slots_.size() * 2, Slot{0, 0, 0, kEmpty});
  old.swap(slots_);
  mask_ = slots_.size() - 1;
  for (const Slot& slot : old) {
    if (slot.index == kEmpty) continue;
    std::uint64_t s = hash_float_point(slot.x, slot.y, slot.z) & mask_;
    while (slots_[s].index != kEmpty) s = (s + 1) & mask_;
    slots_[s] = slot;
  }
}

}  // namespace polyaxis::io
