#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "budget_slam/metrics/RelocalizationCoverage.h"

namespace budget_slam::runs {

/// Relocalization coverage of a run's final map (docs/OUTPUTS.md): the coverage, the steps with
/// their counts against the final map, and where the observations came from.
struct FinalRelocCoverage {
  metrics::RelocalizationCoverage coverage;
  std::vector<metrics::ObservedAtStep> steps;
  std::string source;  ///< landmark_ids | own_association | reference_association | ...
  nlohmann::json details = nlohmann::json::object();  ///< extra fields for summary.json
};

}  // namespace budget_slam::runs
