// The compiled part of the `polyaxis` Python package (python/polyaxis/__init__.py re-exports it).
#include "bindings.h"

PYBIND11_MODULE(_polyaxis, m) {
  m.doc() = "polyaxis: multi-axis process planning (read, inspect, slice, analyze, plan, simulate, laminate)";
  polyaxis::python::bind_errors(m);
  polyaxis::python::bind_options(m);
  polyaxis::python::bind_results(m);
  polyaxis::python::bind_calls(m);
}
