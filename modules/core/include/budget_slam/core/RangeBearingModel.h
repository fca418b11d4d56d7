#pragma once
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>

namespace budget_slam {

/// A 2D range-bearing reading of a landmark at `landmark` by a sensor mounted at `sensor` (its
/// pose in the robot frame) on a robot at `robot` (MRPT's CRangeBearingKFSLAM2D observation
/// model): z = (range [m], bearing [rad] in the sensor frame), with its Jacobians.
struct RangeBearingPrediction {
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> H_robot = Eigen::Matrix<double, 2, 3>::Zero();  ///< dz / (x, y, yaw)
  Eigen::Matrix2d H_landmark = Eigen::Matrix2d::Zero();                       ///< dz / (lx, ly)
};

/// The reading predicted for a landmark at distance > 0 from the sensor, and its Jacobians.
RangeBearingPrediction predictRangeBearing(const mrpt::math::TPose2D& robot,
                                           const mrpt::math::TPose2D& sensor,
                                           const Eigen::Vector2d& landmark);

/// Where a reading (range [m], bearing [rad] in the sensor frame) puts the landmark, in the robot
/// frame [m].
Eigen::Vector2d readingInRobotFrame(double range, double bearing,
                                    const mrpt::math::TPose2D& sensor);

/// The Fisher information about the robot pose (x, y, yaw) of one reading: H^T R^-1 H with
/// H = dz/d(x, y, yaw) and R = diag(std_range^2, std_bearing^2) [m, rad]. Rank 2 at most: one
/// landmark leaves the rotation of the robot about it unobserved.
Eigen::Matrix3d readingInformation(const Eigen::Matrix<double, 2, 3>& H_robot, double std_range,
                                   double std_bearing);

}  // namespace budget_slam
