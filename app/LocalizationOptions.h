#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::app {

/// [Localization]: `budget-slam localize` and `compare --relocalize` (docs/OUTPUTS.md). MRPT's
/// EKF options ([RangeBearingKFSLAM], [RangeBearingKFSLAM_KalmanFilter]) apply as for mapping.
struct LocalizationOptions : public TabledOptions<LocalizationOptions> {
  static constexpr const char* kSection = "Localization";

  double lost_threshold = 1.0;  ///< a step is lost when its position error is above [m]. Default: 1
  double start_std_xy = 0.1;    ///< start pose uncertainty, x and y, 1 sigma [m]. Default: 0.1
  double start_std_yaw_deg = 2.0;  ///< start pose uncertainty, yaw, 1 sigma [deg]. Default: 2
  /// Innovation gate on each paired reading, chi-square with 2 degrees of freedom (13.8: 99.9%);
  /// 0: none, as MRPT's filter (readings paired by sensor ID are known correspondences). Default: 0
  double gate_chi2 = 0;
  std::size_t max_map_landmarks = 2000;  ///< larger maps are refused (the EKF's covariance is
                                         ///< dense: 2000 landmarks = 128 MB). Default: 2000
  std::size_t max_steps =
      0;  ///< localize only the first steps of the traversal; 0: all. Default: 0

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<LocalizationOptions>& table();
};

}  // namespace budget_slam::app
