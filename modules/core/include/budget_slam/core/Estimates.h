#pragma once
#include <Eigen/Core>
#include <cstddef>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Pose2.h"

namespace budget_slam {

/// What a reducer may know of a landmark (docs/ARCHITECTURE.md "Data flow").
struct LandmarkView {
  LandmarkId id = kNoLandmarkId;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  ///< [m]
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();   ///< marginal covariance [m^2]
  std::size_t n_obs = 0;                           ///< number of sightings so far
  /// Running mean of the robot positions the landmark was seen from (Hochdorfer & Schlegel
  /// Eq. 1-2) [m].
  Eigen::Vector2d obs_mean = Eigen::Vector2d::Zero();
  StepIndex first_step = 0;
  StepIndex last_step = 0;
};

/// Robot pose mean and its 3x3 marginal covariance (x, y, yaw).
struct PoseEstimate {
  Pose2 mean;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
};

/// One pose of the estimated trajectory: for the EKF the filter mean after each step, for the
/// graph backend the smoothed estimate of each pose still in the graph.
struct TrajectoryPoint {
  StepIndex step = 0;
  double t = 0;  ///< [s]
  Pose2 pose;
};

/// A variable of the estimate, for joint covariances.
struct VariableKey {
  enum class Kind { Pose, Landmark };
  Kind kind = Kind::Landmark;
  std::int64_t id = 0;  ///< StepIndex for a pose, LandmarkId for a landmark
  static VariableKey pose(StepIndex s) { return {Kind::Pose, static_cast<std::int64_t>(s)}; }
  static VariableKey landmark(LandmarkId l) { return {Kind::Landmark, l}; }
  std::size_t dim() const { return kind == Kind::Pose ? 3 : 2; }
};

}  // namespace budget_slam
