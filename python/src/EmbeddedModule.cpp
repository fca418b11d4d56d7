// budget_slam._core built into the budget-slam executable for --plugin (PluginHost.cpp).
#include <pybind11/embed.h>

#include "CoreModule.h"

PYBIND11_EMBEDDED_MODULE(_core, m) { budget_slam::python::defineCoreModule(m); }
