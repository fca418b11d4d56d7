#pragma once
#include <Eigen/Core>
#include <cmath>

namespace budget_slam {

/// SE(2) helpers on the parameter vector (x [m], y [m], yaw [rad]) of a pose in the world frame,
/// shared by the graph backend and the wake-up on a saved map. The graph perturbs poses additively
/// in these parameters (x <- x + dx, yaw wrapped), so every Jacobian below is with respect to (x,
/// y, yaw) and every covariance it yields is a covariance of (x, y, yaw): the convention of MRPT's
/// CPosePDFGaussian and of Backend::robotPose().
using Pose2 = Eigen::Vector3d;

/// Wraps an angle to [-pi, pi].
inline double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return a - M_PI;
}

inline Eigen::Matrix2d rot2(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

/// a (+) b: the pose b, given in the frame of a, expressed in the world frame.
/// Optional Jacobians of the result with respect to a and to b.
inline Pose2 compose(const Pose2& a, const Pose2& b, Eigen::Matrix3d* Ja = nullptr,
                     Eigen::Matrix3d* Jb = nullptr) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  Pose2 r(a.x() + c * b.x() - s * b.y(), a.y() + s * b.x() + c * b.y(), wrapAngle(a.z() + b.z()));
  if (Ja) {
    *Ja << 1, 0, -s * b.x() - c * b.y(),  //
        0, 1, c * b.x() - s * b.y(),      //
        0, 0, 1;
  }
  if (Jb) {
    *Jb << c, -s, 0,  //
        s, c, 0,      //
        0, 0, 1;
  }
  return r;
}

/// a^-1 (+) b: the pose b expressed in the frame of a (the odometry increment from a to b).
/// Optional Jacobians with respect to a and to b.
inline Pose2 between(const Pose2& a, const Pose2& b, Eigen::Matrix3d* Ja = nullptr,
                     Eigen::Matrix3d* Jb = nullptr) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  Pose2 r(c * dx + s * dy, -s * dx + c * dy, wrapAngle(b.z() - a.z()));
  if (Ja) {
    *Ja << -c, -s, -s * dx + c * dy,  //
        s, -c, -c * dx - s * dy,      //
        0, 0, -1;
  }
  if (Jb) {
    *Jb << c, s, 0,  //
        -s, c, 0,    //
        0, 0, 1;
  }
  return r;
}

}  // namespace budget_slam
