#pragma once
#include <Eigen/Core>

#include "budget_slam/core/Pose2.h"

namespace budget_slam::graph {

using budget_slam::between;
using budget_slam::compose;
using budget_slam::Pose2;
using budget_slam::wrapAngle;

/// A square root S of the information, S^T S = cov^-1 (S = L^-1 for cov = L L^T): whitening a
/// residual e by S turns the factor's Mahalanobis cost e^T cov^-1 e into |S e|^2 (square-root
/// information, Dellaert & Kaess 2006).
/// Throws std::invalid_argument when cov is not symmetric positive definite.
Eigen::Matrix3d sqrtInformation(const Eigen::Matrix3d& cov);
Eigen::Matrix2d sqrtInformation(const Eigen::Matrix2d& cov);

/// Gaussian prior on one pose: e = (x - mean) with the heading difference wrapped.
struct PriorFactor {
  Pose2 mean;                                               ///< [m, m, rad]
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();        ///< [m^2, m^2, rad^2]
  Eigen::Matrix3d sqrt_info = Eigen::Matrix3d::Identity();  ///< sqrtInformation(cov)

  static PriorFactor make(const Pose2& mean, const Eigen::Matrix3d& cov);
  /// Unwhitened residual; J = de/dx.
  Eigen::Vector3d error(const Pose2& x, Eigen::Matrix3d* J = nullptr) const;
};

/// Odometry between two poses, as MRPT's CActionRobotMovement2D gives it: the mean increment z in
/// the frame of the first pose and the covariance of its parameters (dx, dy, dyaw).
/// e = between(xi, xj) - z, yaw wrapped (the additive-noise model of CPosePDFGaussian).
struct BetweenFactor {
  Pose2 z;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d sqrt_info = Eigen::Matrix3d::Identity();

  static BetweenFactor make(const Pose2& z, const Eigen::Matrix3d& cov);
  Eigen::Vector3d error(const Pose2& xi, const Pose2& xj, Eigen::Matrix3d* Ji = nullptr,
                        Eigen::Matrix3d* Jj = nullptr) const;
};

/// A range [m] and bearing [rad] reading of a landmark l (world x, y) by a sensor mounted at
/// `sensor` (its pose on the robot) on the robot at pose x: the prediction is the one sensor model
/// (budget_slam/core/RangeBearingModel.h, predictRangeBearing);
/// e = (range - z_range, wrap(bearing - z_bearing)).
struct RangeBearingFactor {
  double range = 0;                                   ///< [m]
  double bearing = 0;                                 ///< [rad], sensor frame
  Pose2 sensor;                                       ///< sensor pose on the robot
  Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();  ///< [m^2, rad^2]
  Eigen::Matrix2d sqrt_info = Eigen::Matrix2d::Identity();

  static RangeBearingFactor make(double range, double bearing, const Pose2& sensor,
                                 const Eigen::Matrix2d& cov);
  /// The predicted (range, bearing) of l seen from x, with its Jacobians.
  Eigen::Vector2d predict(const Pose2& x, const Eigen::Vector2d& l,
                          Eigen::Matrix<double, 2, 3>* Jx = nullptr,
                          Eigen::Matrix2d* Jl = nullptr) const;
  Eigen::Vector2d error(const Pose2& x, const Eigen::Vector2d& l,
                        Eigen::Matrix<double, 2, 3>* Jx = nullptr,
                        Eigen::Matrix2d* Jl = nullptr) const;
  /// The landmark position this reading implies from pose x (initialisation at first sighting).
  Eigen::Vector2d landmarkFrom(const Pose2& x) const;
};

/// A Gaussian prior on a landmark: what remains of sightings whose poses left the graph
/// (FactorGraph::dropFirstPoses). e = x - mean, whitened by sqrt_info (sqrt_info^T sqrt_info =
/// cov^-1).
struct LandmarkPrior {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  ///< [m]
  Eigen::Matrix2d sqrt_info = Eigen::Matrix2d::Identity();
  /// Throws std::invalid_argument when cov is not positive definite.
  static LandmarkPrior make(const Eigen::Vector2d& mean, const Eigen::Matrix2d& cov);
};

/// The single odometry factor that replaces a -> b (x_i -> x_j -> x_k) when x_j is marginalized:
/// mean z_a (+) z_b, covariance by first-order propagation J_a C_a J_a^T + J_b C_b J_b^T with J the
/// Jacobians of the composition (exact in the linearized problem, see tests).
BetweenFactor composeBetween(const BetweenFactor& a, const BetweenFactor& b);

}  // namespace budget_slam::graph
