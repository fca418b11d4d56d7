#pragma once
#include <Eigen/Core>
#include <cmath>

namespace budget_slam {

/// Wraps an angle [rad] to [-pi, pi] (fmod based; every pose operation below wraps with it).
inline double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return a - M_PI;
}

/// The rotation by `yaw` [rad].
inline Eigen::Matrix2d rot2(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

/// A pose in the plane, SE(2): position (x, y) [m] and heading phi [rad], of a frame (a robot, a
/// sensor) in the frame it is given in (the world, the robot). The members are named as MRPT's
/// TPose2D's, which a pose becomes only where an MRPT call needs one (MrptPose.h).
///
/// The operations follow GTSAM's Pose2 (compose, inverse, between, transformFrom, transformTo),
/// but every Jacobian is with respect to the parameters (x, y, phi), not to a tangent-space
/// perturbation: the graph and the wake-up perturb poses additively in these parameters (x <- x
/// + dx, phi wrapped), and every covariance is a covariance of (x, y, phi), the convention of
/// MRPT's CPosePDFGaussian and of Backend::robotPose().
struct Pose2 {
  double x = 0;    ///< [m]
  double y = 0;    ///< [m]
  double phi = 0;  ///< heading [rad]

  Pose2() = default;
  constexpr Pose2(double x_, double y_, double phi_) : x(x_), y(y_), phi(phi_) {}
  /// From the parameter vector (x, y, phi), as it is held by a solver.
  explicit Pose2(const Eigen::Vector3d& v) : x(v.x()), y(v.y()), phi(v.z()) {}

  /// The parameter vector (x, y, phi).
  Eigen::Vector3d vector() const { return Eigen::Vector3d(x, y, phi); }
  /// The position (x, y) [m].
  Eigen::Vector2d translation() const { return Eigen::Vector2d(x, y); }
  /// The rotation R(phi): a direction in this pose's frame to the frame it is given in.
  Eigen::Matrix2d rotation() const { return rot2(phi); }

  /// The pose whose composition with this one is the identity; J = d(inverse)/d(this).
  Pose2 inverse(Eigen::Matrix3d* J = nullptr) const;

  /// A point given in this pose's frame, in the frame this pose is given in: t + R p.
  /// Jacobians with respect to this pose's parameters and to the point.
  Eigen::Vector2d transformFrom(const Eigen::Vector2d& p,
                                Eigen::Matrix<double, 2, 3>* J_pose = nullptr,
                                Eigen::Matrix2d* J_point = nullptr) const;

  /// A point given in the frame this pose is given in, in this pose's frame: R^T (p - t).
  /// Jacobians with respect to this pose's parameters and to the point.
  Eigen::Vector2d transformTo(const Eigen::Vector2d& p,
                              Eigen::Matrix<double, 2, 3>* J_pose = nullptr,
                              Eigen::Matrix2d* J_point = nullptr) const;
};

/// a (+) b: the pose b, given in the frame of a, expressed in the frame a is given in (heading
/// wrapped). Optional Jacobians of the result with respect to a and to b.
Pose2 compose(const Pose2& a, const Pose2& b, Eigen::Matrix3d* Ja = nullptr,
              Eigen::Matrix3d* Jb = nullptr);

/// a^-1 (+) b: the pose b expressed in the frame of a (the odometry increment from a to b),
/// heading wrapped. Optional Jacobians with respect to a and to b.
Pose2 between(const Pose2& a, const Pose2& b, Eigen::Matrix3d* Ja = nullptr,
              Eigen::Matrix3d* Jb = nullptr);

}  // namespace budget_slam
