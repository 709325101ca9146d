// A counting sort in parallel parts: the items are cut into one contiguous part per thread, each
// part counts its entries per bucket, the counts become slots bucket by bucket and part by part,
// and each part places its own entries. Within a bucket the entries come in item order, so the
// result does not depend on the thread count. Header-only; the caller links oneTBB.
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace polyaxis::core {

// Items per part below which one part does it all.
inline constexpr std::size_t kMinItemsPerPart = std::size_t{1} << 16;

// EMIT(i, put) calls put(bucket, value) for each entry of item i (the same entries each time it
// is called: it runs twice). Fills OUT with the values bucket by bucket and returns the bucket
// starts (BUCKETS + 1 of them). Memory: 4 bytes per bucket and part, besides OUT.
template <class Value, class Emit>
std::vector<std::uint32_t> bucket_in_parts(std::size_t items, std::size_t buckets, std::vector<Value>& out, Emit emit) {
  const auto threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t parts = std::clamp<std::size_t>(items / kMinItemsPerPart, 1, threads);
  auto first_item = [&](std::size_t p) { return items * p / parts; };
  std::vector<std::vector<std::uint32_t>> place(parts);  // per part: counts, then next slot per bucket
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
    std::vector<std::uint32_t>& count = place[p];
    count.assign(buckets, 0);
    for (std::size_t i = first_item(p); i < first_item(p + 1); ++i) emit(i, [&](std::size_t bucket, const Value&) { ++count[bucket]; });
  });
  std::vector<std::uint32_t> start(buckets + 1, 0);
  std::uint32_t next = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    start[b] = next;
    for (std::vector<std::uint32_t>& slot : place) {
      const std::uint32_t n = slot[b];
      slot[b] = next;
      next += n;
    }
  }
  start[buckets] = next;
  out.resize(next);
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
    std::vector<std::uint32_t>& slot = place[p];
    for (std::size_t i = first_item(p); i < first_item(p + 1); ++i) emit(i, [&](std::size_t bucket, const Value& v) { out[slot[bucket]++] = v; });
  });
  return start;
}

}  // namespace polyaxis::core
