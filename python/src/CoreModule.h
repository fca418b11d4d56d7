#pragma once
// The budget_slam._core module's contents (module.cpp and the parts it defines, Bindings.h),
// compiled once: the Python extension (ExtensionModule.cpp) and the module built into budget-slam
// for --plugin (EmbeddedModule.cpp) each register them under their own entry point.
#include <pybind11/pybind11.h>

namespace budget_slam::python {

/// Defines every function and class of budget_slam._core on `m`.
void defineCoreModule(pybind11::module_& m);

}  // namespace budget_slam::python
