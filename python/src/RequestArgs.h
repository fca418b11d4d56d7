#pragma once
// The typed requests of the Python module's commands, filled from their arguments with the
// command line's checks (BudgetSlamApp::initialize), in its order and with its messages.
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include "budget_slam/runs/Request.h"

namespace budget_slam::python {

/// The typed request of run() (runs::RunRequest) and of compare() (runs::CompareRequest) from
/// their arguments (python/budget_slam/__init__.py _invoke). A refused value raises ConfigError.
runs::RunRequest runRequestOf(const pybind11::dict& d);
runs::CompareRequest compareRequestOf(const pybind11::dict& d);

/// The typed request of localize() from its arguments (budget_slam.localize). The checks the
/// command line makes before anything runs raise ConfigError with its text: a bad start pose,
/// wake_up with a start pose, an empty value, a bad max_steps.
runs::LocalizeRequest localizeRequestOf(const std::optional<std::string>& config,
                                        const std::optional<std::string>& rawlog,
                                        const std::string& map, const std::string& outdir,
                                        const std::vector<std::string>& sets,
                                        const std::optional<std::string>& start_pose, bool wake_up,
                                        const std::optional<std::string>& reference_trajectory,
                                        const std::optional<std::string>& max_steps, bool force);

}  // namespace budget_slam::python
