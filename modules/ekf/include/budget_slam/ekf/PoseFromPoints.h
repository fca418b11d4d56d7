#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "budget_slam/core/Estimates.h"

namespace budget_slam::ekf {

/// A landmark seen from the robot: where a reading puts it in the robot's frame and where the
/// map has it, each with its 2x2 covariance [m, m^2].
struct PointMatch {
  Eigen::Vector2d in_robot = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov_in_robot = Eigen::Matrix2d::Zero();
  Eigen::Vector2d in_map = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov_in_map = Eigen::Matrix2d::Zero();
};

/// The robot pose that brings the points seen onto the map's: m_i = R(yaw) q_i + t.
struct PoseFit {
  PoseEstimate pose;    ///< mean and covariance (inverse of the fit's information)
  double worst_d2 = 0;  ///< largest e' C^-1 e of a point at the fit (chi-square, 2 dof)
};

/// Weighted least squares (the closed-form rigid fit, then Gauss-Newton with each point's
/// covariance C_i = cov_in_map + R cov_in_robot R'). nullopt when the map points are fewer than
/// two distinct ones (a 2D pose needs two points) or the fit is not finite.
std::optional<PoseFit> fitPose(const std::vector<PointMatch>& matches);

}  // namespace budget_slam::ekf
