#include "budget_slam/core/RangeBearingModel.h"

#include <cmath>

namespace budget_slam {

RangeBearingPrediction predictRangeBearing(const Pose2& robot, const Pose2& sensor,
                                           const Eigen::Vector2d& landmark) {
  const double c = std::cos(robot.phi), s = std::sin(robot.phi);
  // The sensor's position in the world and its derivative with respect to the robot's heading.
  const Eigen::Vector2d offset(c * sensor.x - s * sensor.y, s * sensor.x + c * sensor.y);
  const Eigen::Vector2d d_offset_dphi(-offset.y(), offset.x());
  // (l - t) - offset: the order of the graph's factors, whose outputs it keeps to the bit.
  const Eigen::Vector2d d = (landmark - Eigen::Vector2d(robot.x, robot.y)) - offset;
  const double r2 = d.squaredNorm(), r = std::sqrt(r2);
  RangeBearingPrediction p;
  p.z = Eigen::Vector2d(r, wrapAngle(std::atan2(d.y(), d.x()) - robot.phi - sensor.phi));
  // dz/d(the sensor's position in the world): range -d^T / r, bearing (d_y, -d_x) / r^2; the
  // bearing has the extra -1 of the frame's heading (the robot's and the sensor's).
  Eigen::Matrix2d dz_ds;
  dz_ds << -d.x() / r, -d.y() / r, d.y() / r2, -d.x() / r2;
  p.H_robot.leftCols<2>() = dz_ds;
  p.H_robot.col(2) = dz_ds * d_offset_dphi + Eigen::Vector2d(0, -1);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  p.H_sensor.leftCols<2>() = dz_ds * R;
  p.H_sensor.col(2) = Eigen::Vector2d(0, -1);
  p.H_landmark = -dz_ds;
  return p;
}

Eigen::Vector2d readingPoint(double range, double bearing, const Pose2& sensor,
                             Eigen::Matrix<double, 2, 3>* J_sensor, Eigen::Matrix2d* J_reading) {
  const double a = sensor.phi + bearing, c = std::cos(a), s = std::sin(a);
  if (J_sensor) *J_sensor << 1, 0, -range * s, 0, 1, range * c;
  if (J_reading) *J_reading << c, -range * s, s, range * c;
  return Eigen::Vector2d(sensor.x + range * c, sensor.y + range * s);
}

Eigen::Matrix3d readingInformation(const Eigen::Matrix<double, 2, 3>& H_robot, double std_range,
                                   double std_bearing) {
  const Eigen::Vector2d w(1.0 / (std_range * std_range), 1.0 / (std_bearing * std_bearing));
  return H_robot.transpose() * w.asDiagonal() * H_robot;
}

}  // namespace budget_slam
