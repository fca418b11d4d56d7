#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/NeesAccumulator.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"

namespace budget_slam::app {

/// What a finished run reports (RunDriver::finish): its summary.json and, in memory, the numbers
/// that summary holds, for compare's table and run's last line.
struct RunResult {
  std::string status;  ///< ok | failed | interrupted (summary.json "status")
  std::string error;   ///< why, when not ok
  nlohmann::json summary;
  /// Errors against ground truth and the pose NEES, when the rawlog has ground truth.
  std::optional<metrics::GroundTruthErrors> ground_truth;
  metrics::NeesMean nees;
  metrics::RelocalizationCoverage relocalization;  ///< of the final map
};

}  // namespace budget_slam::app
