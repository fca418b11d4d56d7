#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/SensorNoise.h"

namespace budget_slam::dataset {

/// A dataset turned into budget-slam steps: what a converter or the simulator returns, and what
/// saveDataset() writes as rawlog + ground truth + sidecar ini.
///
/// Conventions shared by every converter and the simulator (docs/DATASETS.md):
///  - every Step is complete: its parsed fields (odometry, scan) hold exactly the values its MRPT
///    objects (action, frame) hold, float-rounded where MRPT stores floats, so a Step read back
///    from the written rawlog equals the Step here;
///  - step k's action moves the robot from pose k-1 (the start pose for k = 0) to pose k, and its
///    frame is observed at pose k;
///  - ground_truth.path, when present, has steps.size() + 1 rows: row 0 is the start pose (the
///    origin of MRPT's filter), row k + 1 the true pose of step k, as MRPT's simul-landmarks
///    writes.
struct ConvertedDataset {
  std::vector<Step> steps;
  GroundTruth ground_truth;  ///< empty when the source has none
  SensorNoise noise;         ///< the sensor the readings come from (sidecar ini)
  /// One line each, written as comments at the top of the sidecar ini: what made the rawlog,
  /// from which input, and the decisions taken (noise, timing, id mapping).
  std::vector<std::string> notes;
};

}  // namespace budget_slam::dataset
