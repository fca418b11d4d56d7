#pragma once
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/metrics/MapAlignment.h"

namespace budget_slam::runs {

/// A run's output folder read back as a map to localize in (budget-slam localize --map RUN_DIR).
struct MapFolder {
  std::string dir;
  std::vector<LandmarkView> landmarks;  ///< RUN_DIR/landmarks.csv
  /// RUN_DIR/summary.json's ground_truth.map_alignment, when the mapping run had ground truth.
  std::optional<metrics::MapAlignment> alignment;
  std::string status;  ///< the mapping run's status ("" when summary.json is absent)
  /// RUN_DIR/trajectory.tum (the mapping run's path in the map's frame), empty when absent: the
  /// area where relocalization is scored (metrics::MappedArea).
  std::vector<Pose2> path;
};

/// Reads RUN_DIR/landmarks.csv (required), RUN_DIR/summary.json and RUN_DIR/trajectory.tum
/// (optional; at most `max_path_poses` rows). Errors are one
/// InputError line naming the folder or file: "map folder 'X': no such folder",
/// "X/landmarks.csv: cannot open (no such file)", "X/landmarks.csv:7: ...",
/// "X/summary.json: not valid JSON (...)", more than `max_landmarks` landmarks.
MapFolder loadMapFolder(const std::string& dir, std::size_t max_landmarks,
                        std::size_t max_path_poses = 50'000'000);

}  // namespace budget_slam::runs
