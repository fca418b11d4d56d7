#pragma once
#include <string>
#include <vector>

#include "budget_slam/session/SessionState.h"

namespace budget_slam::session {

/// The state file's own sections of `state`, in file order: `[session]`, `[resume_options]`,
/// `[landmarks]` and, when the state has a robot, `[robot]` (docs/OUTPUTS.md "Session state").
std::vector<SessionSection> coreSections(const SessionState& state, const std::string& source);

/// Fills state->header, map and robot from the core sections among `sections` and checks them:
/// sizes that agree, ids that are non-negative and unique, positions within +-1e9 m, steps in
/// order, covariances symmetric and positive definite (the robot's jointly with the landmarks),
/// and no field the blocks do not define. InputError naming the section and field otherwise.
/// Sections that are not core ones are left alone. (How many landmarks a file may hold is bounded
/// where it is read, by the values the `[landmarks]` section may declare.)
void readCoreBlocks(const std::vector<SessionSection>& sections, SessionState* state);

/// True for the names coreSections() writes.
bool isCoreSection(const std::string& name);

}  // namespace budget_slam::session
