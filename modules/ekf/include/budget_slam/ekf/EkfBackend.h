#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <optional>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/BackendRegistry.h"
#include "budget_slam/core/LandmarkTracks.h"
#include "budget_slam/ekf/ReducibleKFSLAM2D.h"
#include "budget_slam/gaussian/BlockMutualInformation.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::ekf {

/// The Backend over MRPT's EKF (docs/ARCHITECTURE.md "EKF backend"). Options come from MRPT's own
/// ini sections [RangeBearingKFSLAM] and [RangeBearingKFSLAM_KalmanFilter], as kf-slam loads them.
class EkfBackend : public Backend, public session::SessionStateOwner {
 public:
  static constexpr const char* kName = "ekf";

  explicit EkfBackend(const mrpt::config::CConfigFileBase& ini);

  /// Its registry entry: name, summary, MRPT's kf-slam sections, factory.
  static BackendEntry entry();

  std::string name() const override { return kName; }
  void process(const Step& step) override;
  std::vector<LandmarkView> landmarks() const override;
  std::size_t landmarkCount() const override { return kf_.landmarkCount(); }
  /// From the sighting bookkeeping (no covariance blocks), sorted by id.
  std::vector<LandmarkId> observedAt(StepIndex step) const override;
  PoseEstimate robotPose() const override;
  std::vector<TrajectoryPoint> trajectory() const override { return trajectory_; }
  std::size_t poseCount() const override { return 1; }
  std::vector<LandmarkId> lastAssociation() const override { return last_ids_; }
  void removeLandmark(LandmarkId id) override;
  /// I(L; rest of the state) in bits; one factorization per drop event, updated by Schur
  /// complements across the drops of that event (see gaussian::BlockMutualInformation).
  std::vector<double> informationGain(const std::vector<LandmarkId>& ids) const override;
  Eigen::Matrix2d landmarkCovariance(LandmarkId id) const override;
  /// Only the latest pose (StepIndex of the last processed step) and landmarks.
  Eigen::MatrixXd jointCovariance(const std::vector<VariableKey>& vars) const override;
  /// A copy of the filter (mean, covariance, id map, MRPT options), the sightings and the
  /// trajectory. MRPT's filter copies by value; the sensory frames it keeps are shared read-only.
  std::unique_ptr<Backend> clone() const override;

  /// The whole filter: the landmarks' joint mean and covariance block (the map), the robot with
  /// its cross-covariance, and section `backend.ekf` (the next free id, the last step). Restored
  /// exactly: the resumed filter is the one the last session ended with.
  void saveSession(session::SessionState& state) const override;
  /// A wake-up hands over through the robot block (its pose found on the map, zero
  /// cross-covariance; docs/ALGORITHMS.md "Waking up on a saved map").
  void restoreSession(const session::SessionState& state) override;

  /// false: keep only the latest pose in trajectory() (bounded memory on lifelong runs; the
  /// per-step poses are in the run's steps.csv anyway). Default: true.
  void setKeepTrajectory(bool keep) { keep_trajectory_ = keep; }

  const ReducibleKFSLAM2D& filter() const { return kf_; }
  /// Ids in state order (the EKF's own ordering of the mean and covariance).
  std::vector<LandmarkId> idsInStateOrder() const;

 private:
  std::size_t stateRow(LandmarkId id) const { return 3 + 2 * kf_.indexOf(id); }

  ReducibleKFSLAM2D kf_;
  LandmarkTracks tracks_;  ///< sightings of every landmark (Hochdorfer & Schlegel Eq. 1-2)
  std::vector<TrajectoryPoint> trajectory_;
  bool keep_trajectory_ = true;
  StepIndex last_step_ = 0;
  std::vector<LandmarkId> last_ids_;  ///< lastAssociation()
  /// Valid from the first informationGain() after a step until the next step.
  mutable std::optional<gaussian::BlockMutualInformation> mi_;
};

}  // namespace budget_slam::ekf
