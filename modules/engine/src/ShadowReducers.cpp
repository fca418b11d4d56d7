#include "budget_slam/engine/ShadowReducers.h"

#include <cmath>

#include "budget_slam/report/RunSummaryJson.h"

namespace budget_slam::runs {

nlohmann::json agreementJson(const reducers::BudgetManager& manager) {
  nlohmann::json agreement = nlohmann::json::array();
  for (const auto& a : manager.agreements())
    agreement.push_back({{"a", a.a},
                         {"b", a.b},
                         {"agree", a.agree},
                         {"total", a.total},
                         {"rate", report::jsonNumber(a.total ? a.rate() : NAN)}});
  return agreement;
}

nlohmann::json shadowFailuresJson(const reducers::BudgetManager& manager) {
  nlohmann::json shadow_failures = nlohmann::json::array();
  for (const auto& f : manager.shadowFailures())
    shadow_failures.push_back({{"shadow", f.shadow},
                               {"failures", f.failures},
                               {"first_step", f.first_step},
                               {"last_step", f.last_step},
                               {"first_error", f.first_error}});
  return shadow_failures;
}

std::string shadowFailureLine(const reducers::ShadowFailures& f) {
  return "shadow reducer '" + f.shadow + "' failed at " + std::to_string(f.failures) +
         " drop decision" + (f.failures == 1 ? "" : "s") + " from step " +
         std::to_string(f.first_step) + " to " + std::to_string(f.last_step) +
         " (first: " + f.first_error + "); the active reducer's drops stand";
}

}  // namespace budget_slam::runs
