// Result<T>: the value of an operation that can fail in an expected way, or the Error saying why.
// Expected failures (unreadable file, unrepairable mesh, infeasible plan) travel as Result; only
// broken invariants throw (see POLYAXIS_CHECK in check.h).
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace polyaxis::core {

// Error classes map one to one onto the CLI's documented exit codes (STYLE.md, RELIABILITY.md).
enum class ErrorCode : int {
  kInternal = 1,      // a broken invariant
  kUsage = 2,         // bad usage or parameters
  kInvalidInput = 3,  // unreadable or invalid input
  kInfeasible = 4,    // infeasible plan or unbuildable geometry
  kMachineLimit = 5,  // machine or kinematic limit violated
  kOutput = 6,        // output I/O failure
};

struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string message;  // names the place: file, byte offset, line, facet, layer, region
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : data_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(Error error) : data_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return data_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & { return std::get<0>(data_); }
  const T& value() const& { return std::get<0>(data_); }
  T&& value() && { return std::get<0>(std::move(data_)); }
  const Error& error() const { return std::get<1>(data_); }

 private:
  std::variant<T, Error> data_;
};

// Result<void>.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT(google-explicit-constructor)
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

inline Error make_error(ErrorCode code, std::string message) { return Error{code, std::move(message)}; }

}  // namespace polyaxis::core
