// The Python module's shared pieces: the objects it hands out (each owns its C++ result, and the
// numpy arrays it gives are views into that result kept alive by the object), errors as Python
// exceptions, and the GIL and progress around long calls.
#pragma once

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "polyaxis/core/progress.h"
#include "polyaxis/core/result.h"
#include "polyaxis/mesh/load_part.h"
#include "polyaxis/report/analyze.h"
#include "polyaxis/lamination/job.h"
#include "polyaxis/machine/configs.h"
#include "polyaxis/report/plan_job.h"
#include "polyaxis/slicing/slice.h"

namespace polyaxis::python {

namespace py = pybind11;

// A core::Error crossing into Python: translated to the exception class of its code (errors.cpp).
struct Failure {
  core::Error error;
};

template <typename T>
T take(core::Result<T>&& result) {
  if (!result) throw Failure{result.error()};
  return std::move(result.value());
}

inline void check(const core::Status& status) {
  if (!status) throw Failure{status.error()};
}

// polyaxis.Error and its subclasses, one per exit code, registered on MODULE.
void bind_errors(py::module_& module);

// A part as read and repaired.
struct Part {
  std::shared_ptr<const mesh::LoadedPart> loaded;
  std::string name;  // its path, or the name given to a mesh from arrays
};

// A slicing result, owning its layers.
struct Slices {
  std::shared_ptr<const slicing::SliceResult> result;
  std::string json;  // layers.json
};

struct Analysis {
  std::shared_ptr<const report::PartAnalysis> result;
  std::string json;  // analysis.json
};

struct Plan {
  std::shared_ptr<const report::PlanJob> job;
};

struct Lamination {
  std::shared_ptr<const lamination::LaminateJob> job;
};

// `polyaxis analyze` and `simulate` options as the CLI names them.
struct AnalyzeRequest {
  std::string root_base;  // analysis::parse_root_base
  report::AnalyzeOptions options;
};
struct SimulateRequest {
  machine::ConfigSources configs;
  double path_tolerance_mm = 0.01;
};

// The CLI's defaults of `plan` and `laminate`: the self-intersection check off.
inline report::PlanRequest default_plan_request() {
  report::PlanRequest r;
  r.part.repair.check_self_intersections = false;
  return r;
}
inline lamination::LaminateRequest default_laminate_request() {
  lamination::LaminateRequest r;
  r.part.repair.check_self_intersections = false;
  return r;
}

// SliceOptions.adaptive = {'cusp': ..., ...} (kUsage for an unknown limit).
void set_adaptive(slicing::SliceOptions& options, const py::dict& limits);

// Option objects with the CLI's names (options.cpp) and the result classes (results.cpp).
void bind_options(py::module_& module);
void bind_results(py::module_& module);
// read_part, inspect, slice, analyze, plan, simulate, laminate (calls.cpp).
void bind_calls(py::module_& module);

// A read-only numpy view of ROWS x COLS values of type T starting at DATA, ROW_STRIDE bytes apart
// (COLS 0: a one-dimensional array), kept alive by OWNER.
template <typename T>
py::array view(const T* data, std::size_t rows, std::size_t cols, std::size_t row_stride, py::handle owner) {
  static const T kEmpty{};
  if (rows == 0) data = &kEmpty;
  const auto n = static_cast<py::ssize_t>(rows), stride = static_cast<py::ssize_t>(row_stride);
  py::array a = cols == 0 ? py::array(py::dtype::of<T>(), std::vector<py::ssize_t>{n}, std::vector<py::ssize_t>{stride}, data, owner)
                          : py::array(py::dtype::of<T>(), std::vector<py::ssize_t>{n, static_cast<py::ssize_t>(cols)},
                                      std::vector<py::ssize_t>{stride, static_cast<py::ssize_t>(sizeof(T))}, data, owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

// Runs CALL with the GIL released, its progress (a Python callable (stage, done, total, finished)
// or None) reported with the GIL held.
template <typename Call>
auto without_gil(const py::object& progress, Call&& call) {
  core::ProgressCallback callback;
  if (!progress.is_none()) {
    // A handle, not an object: the callback is copied and dropped without the GIL, and PROGRESS,
    // the caller's argument, outlives the call.
    callback = [fn = py::handle(progress)](const core::ProgressEvent& e) {
      py::gil_scoped_acquire gil;
      try {
        fn(std::string(e.stage), e.done, e.total, e.finished);
      } catch (py::error_already_set& error) {
        error.discard_as_unraisable("polyaxis progress callback");
      }
    };
  }
  py::gil_scoped_release release;
  core::ProgressScope scope(std::move(callback));
  return call();
}

}  // namespace polyaxis::python
