// polyaxis.Error(Exception), with `exit_code` (the CLI's exit code for the same failure) and
// `category`, and one subclass per category: UsageError (2), InvalidInputError (3),
// InfeasibleError (4), MachineLimitError (5), OutputError (6), InternalError (1).
#include <array>

#include "bindings.h"

namespace polyaxis::python {
namespace {

struct Category {
  core::ErrorCode code;
  const char* class_name;
  const char* category;
};

constexpr std::array<Category, 6> kCategories{{
    {core::ErrorCode::kInternal, "InternalError", "internal"},
    {core::ErrorCode::kUsage, "UsageError", "usage"},
    {core::ErrorCode::kInvalidInput, "InvalidInputError", "invalid-input"},
    {core::ErrorCode::kInfeasible, "InfeasibleError", "infeasible"},
    {core::ErrorCode::kMachineLimit, "MachineLimitError", "machine-limit"},
    {core::ErrorCode::kOutput, "OutputError", "output"},
}};

// The classes, kept for the translator (module objects live as long as the interpreter).
std::array<PyObject*, kCategories.size()> g_classes{};

}  // namespace

void bind_errors(py::module_& module) {
  PyObject* base = PyErr_NewExceptionWithDoc("polyaxis.Error",
                                             "A polyaxis call failed. exit_code is the CLI's exit code for the same failure, "
                                             "category its name; the message names the place (file, facet, layer, region).",
                                             PyExc_Exception, nullptr);
  module.add_object("Error", py::handle(base));
  py::setattr(base, "exit_code", py::int_(1));
  py::setattr(base, "category", py::str("internal"));
  for (std::size_t i = 0; i < kCategories.size(); ++i) {
    const Category& c = kCategories[i];
    const std::string qualified = std::string("polyaxis.") + c.class_name;
    PyObject* cls = PyErr_NewException(qualified.c_str(), base, nullptr);
    py::setattr(cls, "exit_code", py::int_(static_cast<int>(c.code)));
    py::setattr(cls, "category", py::str(c.category));
    module.add_object(c.class_name, py::handle(cls));
    g_classes[i] = cls;
  }
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Failure& f) {
      PyObject* cls = g_classes[0];
      for (std::size_t i = 0; i < kCategories.size(); ++i) {
        if (kCategories[i].code == f.error.code) cls = g_classes[i];
      }
      PyErr_SetString(cls, f.error.message.c_str());
    }
  });
}

}  // namespace polyaxis::python
