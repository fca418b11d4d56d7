#pragma once
#include <mrpt/math/TPose3D.h>

#include <string>

namespace budget_slam::dataset {

/// The bearing-range sensor a converted or simulated rawlog was made with: what its
/// CObservationBearingRange objects state and what its sidecar ini tells the SLAM backends.
struct SensorNoise {
  double std_range = 0;                      ///< 1-sigma range noise [m]
  double std_yaw = 0;                        ///< 1-sigma bearing noise [rad]
  double min_range = 0;                      ///< shortest reading the sensor reports [m]
  double max_range = 0;                      ///< longest reading the sensor reports [m]
  double fov_yaw = 0;                        ///< total horizontal field of view [rad]
  mrpt::math::TPose3D sensor_pose_on_robot;  ///< sensor pose in the robot frame
};

}  // namespace budget_slam::dataset
