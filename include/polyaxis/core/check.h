// Always-on invariant checks. A failed check is a bug in polyaxis, not bad input: it throws
// InvariantError carrying file:line, which the CLI turns into exit code 1.
#pragma once

#include <stdexcept>
#include <string>

namespace polyaxis::core {

class InvariantError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void fail_check(const char* expr, const char* file, int line, const std::string& what);

}  // namespace polyaxis::core

#define POLYAXIS_CHECK(cond, what)                                              \
  do {                                                                          \
    if (!(cond)) ::polyaxis::core::fail_check(#cond, __FILE__, __LINE__, what); \
  } while (false)
