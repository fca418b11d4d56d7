#pragma once
#include <Eigen/Core>
#include <optional>

#include "budget_slam/core/Backend.h"
#include "budget_slam/gaussian/BlockMutualInformation.h"

namespace budget_slam::gaussian {

/// A Backend that is nothing but a Gaussian over the latest robot pose and the landmarks (the
/// EKF's state): mean and covariance frozen, landmarks removable by exact marginalization, and
/// information gain I(L; rest) = 1/2 log2(|P_LL| |Lambda_LL|) from one factorization updated by
/// Schur complements (BlockMutualInformation, the evaluator the EKF backend itself uses).
///
/// Uses: the disposable copy on which `mi` looks ahead over the whole greedy sequence of
/// Choudhary et al. Alg. 3 (for any backend whose joint covariance reproduces its own
/// information gain, i.e. the EKF), and a realistic state for tests and benchmarks.
class GaussianStateBackend : public Backend {
 public:
  /// `P` is (3 + 2N) square: robot x, y, yaw, then x, y of each landmark in `landmarks` order.
  GaussianStateBackend(std::vector<LandmarkView> landmarks, Eigen::MatrixXd P, StepIndex step = 0);

  /// Snapshot of `backend` after `step`: its landmarks and jointCovariance(latest pose, all
  /// landmarks).
  static GaussianStateBackend snapshot(const Backend& backend, StepIndex step);

  std::string name() const override { return "gaussian"; }
  void process(const Step&) override;  ///< throws std::logic_error: a frozen state
  std::vector<LandmarkView> landmarks() const override { return landmarks_; }
  std::size_t landmarkCount() const override { return landmarks_.size(); }
  PoseEstimate robotPose() const override;
  std::vector<TrajectoryPoint> trajectory() const override { return {}; }
  std::size_t poseCount() const override { return 1; }
  void removeLandmark(LandmarkId id) override;
  std::vector<double> informationGain(const std::vector<LandmarkId>& ids) const override;
  Eigen::Matrix2d landmarkCovariance(LandmarkId id) const override;
  Eigen::MatrixXd jointCovariance(const std::vector<VariableKey>& vars) const override;

  const Eigen::MatrixXd& covariance() const { return P_; }
  /// Forgets the factorization, as a new filter step would (benchmarks time a cold decision).
  void resetCache() const { mi_.reset(); }

 private:
  std::size_t row(LandmarkId id) const;  ///< throws std::out_of_range

  std::vector<LandmarkView> landmarks_;
  Eigen::MatrixXd P_;
  StepIndex step_;
  mutable std::optional<BlockMutualInformation> mi_;
};

}  // namespace budget_slam::gaussian
