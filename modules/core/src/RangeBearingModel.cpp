#include "budget_slam/core/RangeBearingModel.h"

#include <cmath>

namespace budget_slam {

RangeBearingPrediction predictRangeBearing(const mrpt::math::TPose2D& robot,
                                           const mrpt::math::TPose2D& sensor,
                                           const Eigen::Vector2d& landmark) {
  const double c = std::cos(robot.phi), s = std::sin(robot.phi);
  // The sensor's position in the world and its derivative with respect to the robot's yaw.
  const Eigen::Vector2d offset(c * sensor.x - s * sensor.y, s * sensor.x + c * sensor.y);
  const Eigen::Vector2d d_offset_dyaw(-offset.y(), offset.x());
  const Eigen::Vector2d d = landmark - (Eigen::Vector2d(robot.x, robot.y) + offset);
  const double r2 = d.squaredNorm(), r = std::sqrt(r2);
  RangeBearingPrediction p;
  p.z = Eigen::Vector2d(
      r, std::remainder(std::atan2(d.y(), d.x()) - robot.phi - sensor.phi, 2 * M_PI));
  // d(range)/d(sensor position) = -d^T / r; d(bearing)/d(sensor position) = (d_y, -d_x) / r^2.
  const Eigen::RowVector2d dr = -d.transpose() / r;
  const Eigen::RowVector2d db = Eigen::RowVector2d(d.y(), -d.x()) / r2;
  p.H_robot << dr(0), dr(1), dr.dot(d_offset_dyaw),  //
      db(0), db(1), db.dot(d_offset_dyaw) - 1.0;
  p.H_landmark << -dr, -db;
  return p;
}

Eigen::Vector2d readingInRobotFrame(double range, double bearing,
                                    const mrpt::math::TPose2D& sensor) {
  const double a = sensor.phi + bearing;
  return Eigen::Vector2d(sensor.x + range * std::cos(a), sensor.y + range * std::sin(a));
}

Eigen::Matrix3d readingInformation(const Eigen::Matrix<double, 2, 3>& H_robot, double std_range,
                                   double std_bearing) {
  const Eigen::Vector2d w(1.0 / (std_range * std_range), 1.0 / (std_bearing * std_bearing));
  return H_robot.transpose() * w.asDiagonal() * H_robot;
}

}  // namespace budget_slam
