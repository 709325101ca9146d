#include "polyaxis/core/check.h"

#include <fmt/format.h>

namespace polyaxis::core {

void fail_check(const char* expr, const char* file, int line, const std::string& what) {
  throw InvariantError(fmt::format("{}:{}: invariant failed: {} ({})", file, line, what, expr));
}

}  // namespace polyaxis::core
