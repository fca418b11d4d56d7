#pragma once
#include <Eigen/Core>

#include "budget_slam/core/Se2.h"

namespace budget_slam::wakeup {

/// A range-bearing reading predicted for a landmark, with its Jacobians (MRPT's
/// CRangeBearingKFSLAM2D observation model): z = (range [m], bearing [rad] in the sensor frame).
struct RangeBearingPrediction {
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> H_robot = Eigen::Matrix<double, 2, 3>::Zero();   ///< dz/d robot
  Eigen::Matrix<double, 2, 3> H_sensor = Eigen::Matrix<double, 2, 3>::Zero();  ///< dz/d sensor
  Eigen::Matrix2d H_landmark = Eigen::Matrix2d::Zero();                        ///< dz/d landmark
};

/// The reading of `landmark` [m] by a sensor at pose `sensor` in the frame of a robot at `robot`
/// (both x, y, yaw), and its Jacobians with respect to the robot pose, the sensor pose on the
/// robot and the landmark. The landmark must not sit on the sensor (range 0).
RangeBearingPrediction predictRangeBearing(const Pose2& robot, const Pose2& sensor,
                                           const Eigen::Vector2d& landmark);

/// Where a reading (range [m], bearing [rad]) of a sensor at pose `sensor` puts the landmark, in
/// the frame `sensor` is given in, with the Jacobians with respect to the sensor pose and to
/// (range, bearing).
Eigen::Vector2d readingPoint(double range, double bearing, const Pose2& sensor,
                             Eigen::Matrix<double, 2, 3>* J_sensor = nullptr,
                             Eigen::Matrix2d* J_reading = nullptr);

}  // namespace budget_slam::wakeup
