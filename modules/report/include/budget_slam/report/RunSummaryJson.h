#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/MapAlignment.h"
#include "budget_slam/metrics/NeesAccumulator.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"

namespace budget_slam::report {

/// A number of summary.json: JSON has no NaN or infinity, so a non-finite value is null.
nlohmann::json jsonNumber(double v);

/// summary.json "ground_truth" (docs/OUTPUTS.md): the files, the errors against them, the pose
/// NEES and, when fitted, where the ground truth's frame sits in the map's (`map_alignment`,
/// where `budget-slam localize` starts another traversal's robot).
nlohmann::json groundTruthJson(const dataset::GroundTruth& truth,
                               const metrics::GroundTruthErrors& errors,
                               const metrics::NeesMean& nees,
                               const std::optional<metrics::MapAlignment>& alignment);

/// summary.json "relocalization": the final map's coverage of the run's steps, where the
/// observations came from (`source`) and any extra fields (`details`).
nlohmann::json relocalizationJson(const metrics::RelocalizationCoverage& coverage,
                                  const std::string& source, const nlohmann::json& details);

}  // namespace budget_slam::report
