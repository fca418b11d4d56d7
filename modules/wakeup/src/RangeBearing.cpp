#include "budget_slam/wakeup/RangeBearing.h"

#include <cmath>

namespace budget_slam::wakeup {

RangeBearingPrediction predictRangeBearing(const Pose2& robot, const Pose2& sensor,
                                           const Eigen::Vector2d& landmark) {
  const Eigen::Matrix2d R = rot2(robot.z());
  // The sensor's position in the world, and its derivative with respect to the robot's yaw.
  const Eigen::Vector2d offset = R * sensor.head<2>();
  const Eigen::Vector2d d_offset_dyaw(-offset.y(), offset.x());
  const Eigen::Vector2d d = landmark - (robot.head<2>() + offset);
  const double r2 = d.squaredNorm(), r = std::sqrt(r2);
  RangeBearingPrediction p;
  p.z = Eigen::Vector2d(r, wrapAngle(std::atan2(d.y(), d.x()) - robot.z() - sensor.z()));
  // dz/d(sensor position in the world): range -d^T / r, bearing (d_y, -d_x) / r^2.
  Eigen::Matrix2d dz_ds;
  dz_ds << -d.x() / r, -d.y() / r, d.y() / r2, -d.x() / r2;
  p.H_robot.leftCols<2>() = dz_ds;
  p.H_robot.col(2) = dz_ds * d_offset_dyaw + Eigen::Vector2d(0, -1);
  p.H_sensor.leftCols<2>() = dz_ds * R;
  p.H_sensor.col(2) = Eigen::Vector2d(0, -1);
  p.H_landmark = -dz_ds;
  return p;
}

Eigen::Vector2d readingPoint(double range, double bearing, const Pose2& sensor,
                             Eigen::Matrix<double, 2, 3>* J_sensor, Eigen::Matrix2d* J_reading) {
  const double a = sensor.z() + bearing, c = std::cos(a), s = std::sin(a);
  if (J_sensor) *J_sensor << 1, 0, -range * s, 0, 1, range * c;
  if (J_reading) *J_reading << c, -range * s, s, range * c;
  return Eigen::Vector2d(sensor.x() + range * c, sensor.y() + range * s);
}

}  // namespace budget_slam::wakeup
