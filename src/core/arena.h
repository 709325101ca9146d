// Runs a call on at most a given number of worker threads, for that call only: a oneTBB task arena
// of that size (a thread count of 0 runs it in the caller's arena, all cores by default). Unlike
// tbb::global_control, two calls with different counts on two threads do not limit each other.
#pragma once

#include <tbb/task_arena.h>

namespace polyaxis::core {

template <typename Call>
auto with_threads(int threads, Call&& call) {
  if (threads <= 0) return call();
  tbb::task_arena arena(threads);
  return arena.execute(call);
}

}  // namespace polyaxis::core
