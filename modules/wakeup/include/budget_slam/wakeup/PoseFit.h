#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/wakeup/ReadingWindow.h"

namespace budget_slam::wakeup {

/// The rigid motion (rotation, then translation) that best maps the points `local` onto `map` in
/// the weighted least-squares sense, min sum_i w_i |R(yaw) local_i + t - map_i|^2, in closed form
/// (centroids, then the angle of the weighted cross-covariance: the 2D case of Umeyama 1991
/// without scale). Returned as the pose (t_x, t_y, yaw) of the local frame in the map. None when
/// the local points do not fix an angle (fewer than two distinct points).
std::optional<Pose2> fitRigid(const std::vector<Eigen::Vector2d>& local,
                              const std::vector<Eigen::Vector2d>& map,
                              const std::vector<double>& weights);

/// A reading paired with a map landmark.
struct Pairing {
  std::size_t reading = 0;   ///< index into the readings
  std::size_t landmark = 0;  ///< index into the map
};

/// The robot pose refined on the range-bearing model.
struct Refinement {
  Pose2 pose;                                     ///< the robot at the latest step, in the map
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  ///< (J^T S^-1 J)^-1 at the solution
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  ///< J^T S^-1 J
  std::vector<double> chi2;  ///< squared Mahalanobis innovation of each pairing, in order
  bool converged = false;
};

/// Gauss-Newton on the readings' innovations from `start`: each reading i, taken by the sensor
/// at `readings[i].sensor` in the latest robot frame, predicted from the robot pose X as
/// h(X (+) sensor, landmark) (predictRangeBearing with the sensor as the offset), weighted by
/// S_i = R + H_sensor Sigma_sensor H_sensor^T + H_landmark Sigma_landmark H_landmark^T (reading
/// noise, the odometry since that reading, the landmark's marginal). At most `max_iterations`;
/// stops when a step moves less than 1e-9 m and rad.
Refinement refinePose(const Pose2& start, const std::vector<LocalReading>& readings,
                      const std::vector<LandmarkView>& map, const std::vector<Pairing>& pairs,
                      const ReadingNoise& noise, int max_iterations = 30);

}  // namespace budget_slam::wakeup
