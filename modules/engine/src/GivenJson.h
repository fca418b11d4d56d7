#pragma once
// summary.json's given keys (RunGiven.h), for its one writer and reader (SummaryJson.cpp).
#include <nlohmann/json.hpp>

#include "budget_slam/engine/RunGiven.h"

namespace budget_slam::runs {

/// Every field `g` sets into `j`, one key each (a key of the same name already in `j` replaced).
void addGivenJson(nlohmann::json& j, const RunGiven& g);
/// The given keys of a summary read back: the ones `j` holds with their type (a key of another
/// type is left out); run's wake_up and a run's reference_metrics stay in the document only.
RunGiven readGiven(const nlohmann::json& j);

}  // namespace budget_slam::runs
