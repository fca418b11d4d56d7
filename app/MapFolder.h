#pragma once
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/metrics/MapAlignment.h"

namespace budget_slam::app {

/// A run's output folder read back as a map to localize in (budget-slam localize --map RUN_DIR).
struct MapFolder {
  std::string dir;
  std::vector<LandmarkView> landmarks;  ///< RUN_DIR/landmarks.csv
  /// RUN_DIR/summary.json's ground_truth.map_alignment, when the mapping run had ground truth.
  std::optional<metrics::MapAlignment> alignment;
  std::string status;  ///< the mapping run's status ("" when summary.json is absent)
};

/// Reads RUN_DIR/landmarks.csv (required) and RUN_DIR/summary.json (optional). Errors are one
/// InputError line naming the folder or file: "map folder 'X': no such folder",
/// "X/landmarks.csv: cannot open (no such file)", "X/landmarks.csv:7: ...",
/// "X/summary.json: not valid JSON (...)", more than `max_landmarks` landmarks.
MapFolder loadMapFolder(const std::string& dir, std::size_t max_landmarks);

}  // namespace budget_slam::app
