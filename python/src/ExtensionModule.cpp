// budget_slam._core as a Python extension (import budget_slam).
#include "CoreModule.h"

PYBIND11_MODULE(_core, m) { budget_slam::python::defineCoreModule(m); }
