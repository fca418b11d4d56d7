#include "budget_slam/ekf/PoseFromPoints.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>

namespace budget_slam::ekf {

namespace {

Eigen::Matrix2d rotation(double a) {
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}

}  // namespace

std::optional<PoseFit> fitPose(const std::vector<PointMatch>& matches) {
  if (matches.size() < 2) return std::nullopt;
  bool distinct = false;
  for (const auto& m : matches) distinct |= (m.in_map - matches.front().in_map).norm() > 1e-9;
  if (!distinct) return std::nullopt;

  // Closed form (Umeyama without scale): the rotation aligning the centred point sets.
  Eigen::Vector2d cq = Eigen::Vector2d::Zero(), cm = cq;
  for (const auto& m : matches) cq += m.in_robot, cm += m.in_map;
  cq /= static_cast<double>(matches.size());
  cm /= static_cast<double>(matches.size());
  double dot = 0, cross = 0;
  for (const auto& m : matches) {
    const Eigen::Vector2d a = m.in_robot - cq, b = m.in_map - cm;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  double yaw = std::atan2(cross, dot);
  Eigen::Vector2d t = cm - rotation(yaw) * cq;

  // Gauss-Newton on e_i = m_i - R q_i - t, weighted by C_i^-1.
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  for (int iteration = 0; iteration < 5; ++iteration) {
    const Eigen::Matrix2d R = rotation(yaw);
    const Eigen::Matrix2d dR = rotation(yaw + M_PI / 2);  // d R / d yaw
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    info.setZero();
    for (const auto& m : matches) {
      const Eigen::Matrix2d C = m.cov_in_map + R * m.cov_in_robot * R.transpose();
      const Eigen::Matrix2d W = C.inverse();
      Eigen::Matrix<double, 2, 3> J;  // d e / d (tx, ty, yaw)
      J << -Eigen::Matrix2d::Identity(), -dR * m.in_robot;
      const Eigen::Vector2d e = m.in_map - R * m.in_robot - t;
      info += J.transpose() * W * J;
      g += J.transpose() * W * e;
    }
    const Eigen::Vector3d step = -info.ldlt().solve(g);
    if (!step.allFinite()) return std::nullopt;
    t += step.head<2>();
    yaw += step(2);
    if (step.norm() < 1e-12) break;
  }
  PoseFit fit;
  fit.pose.mean = Pose2(t.x(), t.y(), std::remainder(yaw, 2 * M_PI));
  fit.pose.cov = info.inverse();
  const Eigen::Matrix2d R = rotation(yaw);
  for (const auto& m : matches) {
    const Eigen::Matrix2d C = m.cov_in_map + R * m.cov_in_robot * R.transpose();
    const Eigen::Vector2d e = m.in_map - R * m.in_robot - t;
    fit.worst_d2 = std::max(fit.worst_d2, e.dot(C.ldlt().solve(e)));
  }
  if (!fit.pose.cov.allFinite() || !std::isfinite(fit.worst_d2)) return std::nullopt;
  return fit;
}

}  // namespace budget_slam::ekf
