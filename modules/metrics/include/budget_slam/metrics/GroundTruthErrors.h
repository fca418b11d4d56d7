#pragma once
#include <limits>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/metrics/RelativePoseError.h"

namespace budget_slam::metrics {

/// The online estimate of the robot pose after one step (what the filter knew then).
struct PoseRecord {
  StepIndex step = 0;
  PoseEstimate estimate;
};

/// Errors against ground truth (docs/ARCHITECTURE.md "Where each formula lives"), SI units; NaN
/// when not computable.
struct GroundTruthErrors {
  std::size_t poses = 0;                                              ///< poses compared
  double trajectory_rmse = std::numeric_limits<double>::quiet_NaN();  ///< [m]
  double trajectory_max = std::numeric_limits<double>::quiet_NaN();   ///< [m]
  /// The same after the rigid 2D transform that best aligns the trajectory to ground truth (least
  /// squares over positions, no scale: Umeyama / evo's --align). SLAM fixes its frame at the start
  /// pose, so an early heading error rotates the whole estimate; this separates that from shape.
  double trajectory_rmse_aligned = std::numeric_limits<double>::quiet_NaN();  ///< [m]
  double alignment_rotation_deg = std::numeric_limits<double>::quiet_NaN();   ///< of that transform
  /// Drift: the translational relative pose error over pairs of poses 10 m of ground-truth path
  /// apart (RelativePoseError.h, evo_rpe --delta 10 --delta_unit m), RMSE [m per 10 m].
  RelativePoseError rpe;
  std::size_t landmarks = 0;                                        ///< landmarks matched by id
  double landmark_rmse = std::numeric_limits<double>::quiet_NaN();  ///< [m]
  double landmark_rmse_aligned = std::numeric_limits<double>::quiet_NaN();  ///< [m], same transform
};

/// Ground-truth row of step k: MRPT's simul-landmarks writes the start pose as the first row, so
/// step k is row k+1 — unless the path has exactly one row a step, then it is row k. (A run cut
/// short by max_steps sees more rows than steps: still k+1.)
std::size_t groundTruthRow(StepIndex step, std::size_t path_rows, std::size_t steps);

/// Throws Error "<what>: the pose of step k is not finite" (or landmark i): metrics are never
/// computed from a diverged estimate (the caller leaves non-finite values out).
void requireFinite(const std::vector<TrajectoryPoint>& trajectory,
                   const std::vector<LandmarkView>& landmarks, const std::string& what);

/// The estimate starts at the origin; ground truth is brought into that frame by the inverse of
/// its start pose (the row before step 0, or row 0), which is the identity for MRPT's files.
/// Non-finite estimates are an Error (requireFinite). The pose NEES, which needs the online
/// covariances, is accumulated during the run (NeesAccumulator.h).
GroundTruthErrors groundTruthErrors(const std::vector<TrajectoryPoint>& trajectory,
                                    const std::vector<LandmarkView>& landmarks,
                                    const dataset::GroundTruth& truth, std::size_t steps);

/// Ground truth in the estimate's frame: composed with the inverse of its start pose (the first
/// row of the path), so that the start pose becomes the origin the estimate starts from.
dataset::GroundTruth toEstimateFrame(const dataset::GroundTruth& truth);

/// Rigid 2D transform (R, t) minimising sum |R a_i + t - b_i|^2 (Umeyama 1991 without scale).
struct RigidTransform2 {
  Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
  Eigen::Vector2d t = Eigen::Vector2d::Zero();
  Eigen::Vector2d apply(const Eigen::Vector2d& p) const { return R * p + t; }
};
RigidTransform2 alignPoints(const std::vector<Eigen::Vector2d>& a,
                            const std::vector<Eigen::Vector2d>& b);

}  // namespace budget_slam::metrics
