#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "budget_slam/reducers/BudgetManager.h"

namespace budget_slam::runs {

/// summary.json "agreement": how often each pair of active and shadow reducers chose the same
/// landmark (docs/OUTPUTS.md).
nlohmann::json agreementJson(const reducers::BudgetManager& manager);
/// summary.json "shadow_failures": how each shadow reducer that failed failed over the run.
nlohmann::json shadowFailuresJson(const reducers::BudgetManager& manager);

/// One line saying how a shadow reducer failed over a run (a warning on stderr).
std::string shadowFailureLine(const reducers::ShadowFailures& f);

}  // namespace budget_slam::runs
