#pragma once
// Values of budget-slam's flags that TCLAP cannot check by type (docs/OUTPUTS.md "Command line
// and exit codes"): each bad one is a UsageError naming the flag (exit 2, nothing written). The
// checks a request needs whoever fills it are the run layer's (runs/RequestChecks.h).
#include <tclap/ValueArg.h>

#include <string>
#include <vector>

#include "budget_slam/runs/RequestChecks.h"

namespace budget_slam::app {

/// runs::refuseEmptyValue for each of TCLAP's string flags that was given.
void refuseEmptyValues(const std::vector<const TCLAP::ValueArg<std::string>*>& flags);

}  // namespace budget_slam::app
