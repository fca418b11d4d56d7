// reducer_names and registry: the registries' one listing (engine/RegistryListing.h), what
// budget-slam --list prints, without the command line.
#include <pybind11/stl.h>

#include <string>

#include "Bindings.h"
#include "budget_slam/engine/RegistryListing.h"
#include "budget_slam/reducers/BuiltinReducers.h"

namespace py = pybind11;

namespace budget_slam::python {

void defineRegistryBindings(py::module_& m) {
  m.def("reducer_names", [] { return reducers::builtinReducers().names(); });
  m.def(
      "registry", [](const std::string& kind) { return toPython(runs::registryEntries(kind)); },
      py::arg("kind"),
      "The registered reducers or backends (kind: reducers, backends), each a dict: name, "
      "summary, options (section, key, default, doc); what budget-slam --list <kind> --json "
      "prints.");
}

}  // namespace budget_slam::python
