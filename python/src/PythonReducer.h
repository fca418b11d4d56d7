#pragma once
// Reducers written in Python (docs/PYTHON.md "A reducer in Python"): a Python class registered by
// name in the one reducer registry (reducers::builtinReducers()), so that run, compare, the
// sweeps, --list and the ini checks know it as any other reducer.
#include <pybind11/pybind11.h>

namespace budget_slam::python {

/// Defines, in module `m` (budget_slam._core), `register_reducer`, the `Drop` a plugin's choose()
/// is given and the `Seen` its observe() is given.
void definePluginApi(pybind11::module_& m);

}  // namespace budget_slam::python
