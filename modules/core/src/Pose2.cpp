#include "budget_slam/core/Pose2.h"

namespace budget_slam {

// The arithmetic of compose and between (their order of operations included) is the one the
// graph backend and the wake-up were written and checked against; changing it changes their
// outputs in the last bits (tools/check_same_outputs.py).

Pose2 compose(const Pose2& a, const Pose2& b, Eigen::Matrix3d* Ja, Eigen::Matrix3d* Jb) {
  const double c = std::cos(a.phi), s = std::sin(a.phi);
  const Pose2 r(a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrapAngle(a.phi + b.phi));
  if (Ja) {
    *Ja << 1, 0, -s * b.x - c * b.y,  //
        0, 1, c * b.x - s * b.y,      //
        0, 0, 1;
  }
  if (Jb) {
    *Jb << c, -s, 0,  //
        s, c, 0,      //
        0, 0, 1;
  }
  return r;
}

Pose2 between(const Pose2& a, const Pose2& b, Eigen::Matrix3d* Ja, Eigen::Matrix3d* Jb) {
  const double c = std::cos(a.phi), s = std::sin(a.phi);
  const double dx = b.x - a.x, dy = b.y - a.y;
  const Pose2 r(c * dx + s * dy, -s * dx + c * dy, wrapAngle(b.phi - a.phi));
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

Pose2 Pose2::inverse(Eigen::Matrix3d* J) const { return between(*this, Pose2(), J, nullptr); }

Eigen::Vector2d Pose2::transformFrom(const Eigen::Vector2d& p, Eigen::Matrix<double, 2, 3>* J_pose,
                                     Eigen::Matrix2d* J_point) const {
  const double c = std::cos(phi), s = std::sin(phi);
  if (J_pose) {
    *J_pose << 1, 0, -s * p.x() - c * p.y(),  //
        0, 1, c * p.x() - s * p.y();
  }
  if (J_point) *J_point << c, -s, s, c;
  return Eigen::Vector2d(x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y());
}

Eigen::Vector2d Pose2::transformTo(const Eigen::Vector2d& p, Eigen::Matrix<double, 2, 3>* J_pose,
                                   Eigen::Matrix2d* J_point) const {
  const double c = std::cos(phi), s = std::sin(phi);
  const double dx = p.x() - x, dy = p.y() - y;
  if (J_pose) {
    *J_pose << -c, -s, -s * dx + c * dy,  //
        s, -c, -c * dx - s * dy;
  }
  if (J_point) *J_point << c, s, -s, c;
  return Eigen::Vector2d(c * dx + s * dy, -s * dx + c * dy);
}

}  // namespace budget_slam
