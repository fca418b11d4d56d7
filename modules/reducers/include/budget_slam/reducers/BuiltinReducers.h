#pragma once
#include "budget_slam/core/ReducerRegistry.h"

namespace budget_slam::reducers {

/// The registry of every reducer of this build: the ones shipped with budget-slam (one
/// `r.add(X::entry())` line each in BuiltinReducers.cpp) and those added by addReducer. `none`
/// builds no reducer: the unreduced reference run.
const ReducerRegistry& builtinReducers();

/// Adds a reducer compiled into the program but not shipped with budget-slam (a test's, a
/// plug-in's) to builtinReducers(), by one line at namespace scope of its own file:
///   static const bool kAdded = budget_slam::reducers::addReducer(MyReducer::entry());
/// From then on the command line, --list, the ini checks and the runs know it as any other.
/// Returns true; throws std::logic_error when the name is taken. Call it before the first run
/// (static initialization does): the registry is not locked against runs reading it.
bool addReducer(ReducerEntry entry);

}  // namespace budget_slam::reducers
