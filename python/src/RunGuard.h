#pragma once
// How the Python module runs one of the run layer's commands as the command line would: the GIL
// released, the stop signals' handlers installed, Python's progress= as the hooks' callback.
#include <pybind11/pybind11.h>

#include <optional>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/StopSignals.h"
#include "budget_slam/report/Figure.h"
#include "budget_slam/runs/RunHooks.h"

namespace budget_slam::python {

/// A progress report as the dict Python's progress= callback receives (docs/PYTHON.md).
pybind11::dict progressDict(const ProgressSnapshot& s);

/// Python's progress= as a ProgressCallback (none without one). It runs on the calling thread
/// with the GIL taken back; an exception it raises is kept in `error` and stops the run as Ctrl-C
/// does (every output written), to be raised again once the run has ended.
ProgressCallback progressCallback(const std::optional<pybind11::function>& progress,
                                  std::optional<pybind11::error_already_set>& error);

/// Runs `call` (one of the run layer's commands) as the command line would: the GIL released
/// (Ctrl-C then reaches the stop request's handler), the stop signals' handlers installed for the
/// call and a stop request left by an earlier call cleared (as BudgetSlamApp::run), the figure
/// fonts loaded while descriptors are to be had (report/Figure.h), and `progress` as the hooks'
/// callback. What the callback raised is raised again once the call has ended.
template <class Call>
void runGuarded(const std::optional<pybind11::function>& progress, runs::RunHooks& hooks,
                const Call& call) {
  std::optional<pybind11::error_already_set> callback_error;
  hooks.progress.callback = progressCallback(progress, callback_error);
  {
    pybind11::gil_scoped_release release;
    const bool first_guard = !StopSignals::installed();
    StopSignals signals;
    if (first_guard) Cancellation::clear();
    report::loadFigureFonts();
    call();
  }
  if (callback_error) {
    callback_error->restore();
    throw pybind11::error_already_set();
  }
}

}  // namespace budget_slam::python
