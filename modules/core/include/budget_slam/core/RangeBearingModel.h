#pragma once
#include <Eigen/Core>

#include "budget_slam/core/Pose2.h"

namespace budget_slam {

/// The range-bearing sensor model, the one every part uses (the EKF's gates and relocalization,
/// the graph's factors, the wake-up, the reducers): a sensor mounted at `sensor` (its pose on the
/// robot) on a robot at `robot` reads a landmark at `landmark` [m] as
///   d = l - (t + R(phi) s_t),  range = |d|,  bearing = wrap(atan2(d_y, d_x) - phi - s_phi)
/// (MRPT's CRangeBearingKFSLAM2D observation model), with its Jacobians with respect to the robot
/// pose, the sensor pose and the landmark (all with respect to the parameters (x, y, phi)).
struct RangeBearingPrediction {
  Eigen::Vector2d z = Eigen::Vector2d::Zero();  ///< (range [m], bearing [rad] in the sensor frame)
  Eigen::Matrix<double, 2, 3> H_robot = Eigen::Matrix<double, 2, 3>::Zero();   ///< dz/d robot
  Eigen::Matrix<double, 2, 3> H_sensor = Eigen::Matrix<double, 2, 3>::Zero();  ///< dz/d sensor
  Eigen::Matrix2d H_landmark = Eigen::Matrix2d::Zero();                        ///< dz/d landmark
};

/// The reading predicted for a landmark, and its Jacobians. The landmark must not sit on the
/// sensor (range 0: the Jacobians divide by the range).
RangeBearingPrediction predictRangeBearing(const Pose2& robot, const Pose2& sensor,
                                           const Eigen::Vector2d& landmark);

/// Where a reading (range [m], bearing [rad]) of a sensor at pose `sensor` puts the landmark, in
/// the frame `sensor` is given in (the robot frame for the sensor's pose on the robot, the world
/// for the sensor's pose in the world): the inverse of predictRangeBearing. Optional Jacobians
/// with respect to the sensor pose and to (range, bearing).
Eigen::Vector2d readingPoint(double range, double bearing, const Pose2& sensor,
                             Eigen::Matrix<double, 2, 3>* J_sensor = nullptr,
                             Eigen::Matrix2d* J_reading = nullptr);

/// The Fisher information about the robot pose (x, y, phi) of one reading: H^T R^-1 H with
/// H = dz/d(x, y, phi) and R = diag(std_range^2, std_bearing^2) [m, rad]. Rank 2 at most: one
/// landmark leaves the rotation of the robot about it unobserved.
Eigen::Matrix3d readingInformation(const Eigen::Matrix<double, 2, 3>& H_robot, double std_range,
                                   double std_bearing);

}  // namespace budget_slam
