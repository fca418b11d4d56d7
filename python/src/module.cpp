// budget_slam._core: the C++ half of the budget_slam Python module (python/budget_slam/__init__.py
// is the other). It runs `run`, `compare` and `localize` in-process through the run layer with a
// typed request (RunBindings.cpp), gives the typed outcome's words (OutcomeBindings.cpp), lists
// the registries (RegistryBindings.cpp), scores Gaussian states with the registered reducers
// (ReducerScores.cpp) and registers reducers written in Python (PythonReducer.cpp); reading the
// run's files into numpy arrays is left to the Python half.
#include "Bindings.h"
#include "CoreModule.h"
#include "PythonReducer.h"
#include "budget_slam/core/Error.h"

namespace py = pybind11;

namespace budget_slam::python {

void defineCoreModule(py::module_& m) {
  m.doc() = "C++ core of budget_slam: the run layer in-process and the reducer registry";
  static py::exception<budget_slam::ConfigError> config_error(m, "ConfigError", PyExc_ValueError);
  static py::exception<budget_slam::Error> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const budget_slam::ConfigError& e) {
      config_error(e.what());
    } catch (const budget_slam::Error& e) {
      error(e.what());
    }
  });
  defineRunBindings(m);       // run_request, CommandOutcome, localize
  defineOutcomeBindings(m);   // read_summary, summary_keys, exit_code
  defineRegistryBindings(m);  // reducer_names, registry
  defineReducerScores(m);     // reducer_scores
  definePluginApi(m);         // register_reducer, Drop, Seen
}

}  // namespace budget_slam::python
