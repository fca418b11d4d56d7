#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Step.h"

namespace budget_slam {

/// A landmark SLAM estimator the budget manager can shrink (docs/ARCHITECTURE.md "Interfaces").
/// Implemented by the EKF (modules/ekf) and the landmark graph (modules/graph). What only a
/// backend that keeps past poses does is the optional capability PoseHistoryBackend, asked with
/// poseHistory() (as session::SessionStateOwner is).
class Backend {
 public:
  virtual ~Backend() = default;

  /// "ekf" or "graph".
  virtual std::string name() const = 0;

  /// Folds one rawlog step (odometry and bearing-range readings) into the estimate.
  virtual void process(const Step& step) = 0;

  /// Every landmark in the estimate, in a stable order (state order for the EKF).
  virtual std::vector<LandmarkView> landmarks() const = 0;
  virtual std::size_t landmarkCount() const = 0;

  /// Ids of the landmarks that the readings of step `step` were associated with (new landmarks
  /// included), when `step` is the last step processed. The default reads landmarks() and keeps
  /// those whose last_step is `step`; backends override it with their association, which is
  /// cheaper than building every landmark's view.
  virtual std::vector<LandmarkId> observedAt(StepIndex step) const {
    std::vector<LandmarkId> out;
    for (const auto& l : landmarks())
      if (l.last_step == step && l.n_obs > 0) out.push_back(l.id);
    return out;
  }

  /// Latest robot pose and its marginal covariance.
  virtual PoseEstimate robotPose() const = 0;

  /// The estimated trajectory (see TrajectoryPoint).
  virtual std::vector<TrajectoryPoint> trajectory() const = 0;

  /// For each reading of the step last given to process(), in its order: the id of the landmark
  /// the reading was used for (a new landmark's id included), kNoLandmarkId when it was not used.
  /// Read right after process(), before any removal. Empty when the backend does not say.
  virtual std::vector<LandmarkId> lastAssociation() const { return {}; }

  /// Robot poses held in the estimate (1 for the EKF, kept poses for the graph).
  virtual std::size_t poseCount() const = 0;

  /// Drops landmark `id` by exact marginalization; throws std::out_of_range if unknown.
  virtual void removeLandmark(LandmarkId id) = 0;

  /// Information gain of each landmark in bits (docs/ALGORITHMS.md "mi").
  virtual std::vector<double> informationGain(const std::vector<LandmarkId>& ids) const = 0;

  /// Marginal covariance of one landmark [m^2].
  virtual Eigen::Matrix2d landmarkCovariance(LandmarkId id) const = 0;

  /// Joint marginal covariance of the given variables, stacked in order (3 rows a pose:
  /// x, y, yaw; 2 a landmark). The EKF holds only the latest pose.
  virtual Eigen::MatrixXd jointCovariance(const std::vector<VariableKey>& vars) const = 0;

  /// A disposable deep copy for look-ahead (e.g. the whole greedy sequence of Choudhary et al.
  /// Alg. 3 run before the real removals): it evolves independently of this backend and gives
  /// the same estimates, covariances and information gains as this one would after the same
  /// calls. Null when the backend cannot be copied (the BudgetManager then falls back).
  virtual std::unique_ptr<Backend> clone() const { return nullptr; }
};

/// The optional capability of a backend that keeps past poses (full smoothing: the graph), not
/// only the latest one (the EKF).
class PoseHistoryBackend {
 public:
  virtual ~PoseHistoryBackend() = default;
  /// Removes the poses that observe no landmark, except the first and the last `keep_last`
  /// (Choudhary et al. Alg. 3, lines 15-16). Returns how many went.
  virtual std::size_t marginalizePosesWithoutLandmarks(std::size_t keep_last) = 0;
  /// Called once after the last step: the estimate of every kept pose becomes the batch optimum.
  virtual void finish() = 0;
};

/// `backend` as a PoseHistoryBackend, or nullptr when it holds only the latest pose.
inline PoseHistoryBackend* poseHistory(Backend* backend) {
  return dynamic_cast<PoseHistoryBackend*>(backend);
}

}  // namespace budget_slam
