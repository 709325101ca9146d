// A fuzz target's invariant: a breach aborts, which libFuzzer reports as a crash.
#pragma once

#include <cstdlib>

namespace polyaxis::fuzz {

inline void require(bool ok) {
  if (!ok) std::abort();
}

}  // namespace polyaxis::fuzz
