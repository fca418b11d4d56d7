#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::runs {

/// [Localization]: `budget-slam localize` and `compare --relocalize` (docs/OUTPUTS.md). MRPT's
/// EKF options ([RangeBearingKFSLAM], [RangeBearingKFSLAM_KalmanFilter]) apply as for mapping.
struct LocalizationOptions : public TabledOptions<LocalizationOptions> {
  static constexpr const char* kSection = "Localization";

  double lost_threshold = 1.0;  ///< a step is lost when its position error is above [m]. Default: 1
  double start_std_xy = 0.1;    ///< start pose uncertainty, x and y, 1 sigma [m]. Default: 0.1
  double start_std_yaw_deg = 2.0;  ///< start pose uncertainty, yaw, 1 sigma [deg]. Default: 2
  /// Innovation gate on each paired reading, chi-square with 2 degrees of freedom (13.8: 99.9%);
  /// 0: none, as MRPT's filter (docs/ALGORITHMS.md "Relocalization"). Default: 13.8
  double gate_chi2 = 13.8;
  /// Recovery: after this many steps in a row whose paired readings were all rejected, the pose
  /// is solved afresh from those readings; 0: never [steps]. Default: 5
  std::size_t recover_after_steps = 5;
  /// The rejected readings of the last this many steps make the recovery's solve [steps], >= 1.
  /// Default: 20
  std::size_t recovery_window_steps = 20;
  /// Distinct landmarks among those readings that the solve needs, >= 2 (three make a solve
  /// that a few wrong readings cannot fake) [landmarks]. Default: 3
  std::size_t recovery_min_landmarks = 3;
  /// Places of the success per place (as [PlaceCoverageReducer]): the cell side [m] (0 = a quarter
  /// of the traversal's sensor range) and the heading sectors (0 = from its field of view).
  double place_size = 0;
  std::size_t heading_sectors = 0;
  /// A step is tracked when its position error is at most success_xy [m] and its yaw error at
  /// most success_yaw_deg [deg]. Defaults: 0.25, 5
  double success_xy = 0.25;
  double success_yaw_deg = 5;
  std::size_t max_map_landmarks = 2000;  ///< larger maps are refused (the EKF's covariance is
                                         ///< dense: 2000 landmarks = 128 MB). Default: 2000
  std::size_t max_steps =
      0;  ///< localize only the first steps of the traversal; 0: all. Default: 0

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<LocalizationOptions>& table();
};

}  // namespace budget_slam::runs
