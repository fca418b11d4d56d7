#pragma once
#include "budget_slam/core/ReducerRegistry.h"

namespace budget_slam::reducers {

/// The registry of every reducer shipped with budget-slam. `none` builds no reducer: the
/// unreduced reference run.
const ReducerRegistry& builtinReducers();

}  // namespace budget_slam::reducers
