#pragma once
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/metrics/GroundTruthErrors.h"

namespace budget_slam::metrics {

/// Where the ground-truth files' frame sits in a map's frame: x_map = R x_truth + t. A SLAM map is
/// anchored at its run's first pose and carries the heading error made before its first loop
/// closure (44 deg on mrclam7_robot1), so a pose known in the ground-truth frame (another robot's
/// start, another traversal's true path) is brought into the map through this transform.
struct MapAlignment {
  RigidTransform2 transform;
  /// What it was fitted to: "landmarks" (the map's landmarks onto their true positions, matched
  /// by id; at least 3), else "trajectory" (the estimated positions onto the true path; at least
  /// 2), else "start_pose" (the inverse of the true start pose: the map's nominal frame).
  std::string source;
  std::size_t points = 0;  ///< landmarks or poses fitted

  double yaw() const;  ///< rotation angle [rad]
  Pose2 apply(const Pose2& truth_pose) const;
  /// The transform from its pose form (x, y, yaw: rotation by yaw, then translation by (x, y)).
  static MapAlignment fromPose(double x, double y, double yaw, std::string source,
                               std::size_t points);
};

/// Least-squares rigid fit (Umeyama without scale) of the ground truth onto the run's final
/// `landmarks`, else its `trajectory` (rows by groundTruthRow with `steps`); nullopt without any
/// ground truth.
std::optional<MapAlignment> mapAlignment(const std::vector<LandmarkView>& landmarks,
                                         const std::vector<TrajectoryPoint>& trajectory,
                                         const dataset::GroundTruth& truth, std::size_t steps);

}  // namespace budget_slam::metrics
