#pragma once
#include "budget_slam/core/BackendRegistry.h"

namespace budget_slam::runs {

/// The registry of every backend shipped with budget-slam (`ekf`, `graph`): the one place their
/// names, ini sections and factories are listed; the command line, [MappingApplication] backend,
/// the unknown-key check and the run driver all read it.
const BackendRegistry& builtinBackends();

}  // namespace budget_slam::runs
