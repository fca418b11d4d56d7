#pragma once
#include <deque>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/ekf/RangeBearingKF2D.h"

namespace budget_slam::ekf {

/// Localization in a fixed map with MRPT's 2D range-bearing EKF: the filter, its motion and sensor
/// models, its ini sections and its data association are MRPT's CRangeBearingKFSLAM2D, unchanged,
/// and its Kalman iteration is the mapping filter's (RangeBearingKF2D: [EkfSLAM] update, sparse
/// or MRPT's own); what differs (docs/OUTPUTS.md, "budget-slam localize"):
///  - the state starts from a given robot pose and covariance and the map's landmarks (means and
///    marginal 2x2 covariances, no cross-covariances: a saved map keeps only the marginals);
///  - no landmark ever enters: a reading of a landmark not in the map (an unknown sensor ID, or an
///    ID-less reading MRPT's data association leaves unpaired) is not used;
///  - a paired reading whose innovation fails the chi-square gate `gate.chi2` (or whose landmark
///    MRPT does not predict in view) is not used either (gate.chi2 = 0: no gate, MRPT's own
///    behaviour: readings paired by sensor ID are known correspondences);
///  - recovery: when every paired reading of `gate.recover_after_steps` steps in a row was
///    rejected (steps without a paired reading neither count nor break the run), the robot pose
///    is solved afresh from the rejected readings of the last `gate.recovery_window_steps` steps
///    (each brought into the current robot frame by the filter's own motion since: dead
///    reckoning, as no reading was used) against the map's landmarks, by weighted least squares
///    (fitPose). If at least `gate.recovery_min_landmarks` distinct landmarks were read and every
///    reading agrees with the solved pose within the gate, the filter's pose becomes that pose with
///    the fit's covariance, uncorrelated with the map (docs/ALGORITHMS.md "Relocalization: the gate
///    and recovery"); otherwise the filter keeps going and tries again at the next rejected step;
///  - the robot pose is predicted from odometry even while no landmark is in view (MRPT's SLAM
///    filter skips prediction while its map is empty, which would freeze a robot in an empty map).
class LocalizationKF2D : public RangeBearingKF2D {
 public:
  /// The gate on paired readings and the recovery after a run of rejected steps.
  struct Gate {
    double chi2 = 0;  ///< d^2 = v' S^-1 v of a paired reading above this is rejected; 0 = no gate
    std::size_t recover_after_steps =
        0;  ///< steps all rejected in a row before recovery; 0 = never
    std::size_t recovery_window_steps = 0;   ///< readings of the last this many steps are used
    std::size_t recovery_min_landmarks = 3;  ///< distinct landmarks the solve needs, >= 2
  };

  /// Sets the state: `start` (mean and 3x3 covariance) and `map`, whose ids become the filter's
  /// landmark IDs (ID-less readings are paired by MRPT's data association against them).
  void initialize(const PoseEstimate& start, const std::vector<LandmarkView>& map);

  /// One Kalman iteration (RangeBearingKF2D::iterate) on the step's own action and frame.
  void processStep(const Step& step);

  Gate gate;

  PoseEstimate robotPose() const;
  /// The landmarks as the filter now holds them (id, mean, marginal covariance).
  std::vector<LandmarkView> landmarks() const;
  std::size_t landmarkCount() const { return getNumberOfLandmarksInTheMap(); }

  /// Per reading of the last step: the id of the map landmark it updated, or kNoLandmarkId.
  const std::vector<LandmarkId>& lastUsed() const { return used_; }
  /// Readings of the last step paired with a map landmark but rejected by the gate.
  std::size_t lastGated() const { return gated_; }
  /// True when the last step ended with a recovery (the pose solved afresh from readings).
  bool lastRecovered() const { return recovered_; }
  /// Readings of the last step paired with a map landmark where the map says it is: innovation
  /// d^2 within kConsistentChi2, gate or no gate. None over a whole traversal: the map and the
  /// traversal share no place (a map of another world whose sensor IDs happen to repeat).
  std::size_t lastConsistent() const { return consistent_; }
  /// Chi-square, 2 degrees of freedom, 99.9%.
  static constexpr double kConsistentChi2 = 13.8155;

 protected:
  void OnTransitionModel(const KFArray_ACT& in_u, KFArray_VEH& inout_x,
                         bool& out_skipPrediction) const override;
  void OnGetObservationsAndDataAssociation(vector_KFArray_OBS& out_z,
                                           std::vector<int>& out_data_association,
                                           const vector_KFArray_OBS& in_all_predictions,
                                           const KFMatrix& in_S,
                                           const std::vector<size_t>& in_lm_indices_in_S,
                                           const KFMatrix_OxO& in_R) override;
  /// Never reached (no reading is left unpaired); throws std::logic_error if it were.
  void OnNewLandmarkAddedToMap(const size_t in_obsIdx, const size_t in_idxNewFeat) override;

 private:
  /// A paired reading of a step: the landmark's state index and the reading (sensor frame).
  struct PairedReading {
    std::size_t landmark = 0;
    double range = 0, bearing = 0;
  };
  /// A step whose paired readings were all rejected, as the recovery needs it.
  struct RejectedStep {
    std::size_t step = 0;  ///< counter of processStep() calls
    Pose2 robot;           ///< the filter's pose after the step (dead reckoning)
    Pose2 sensor;          ///< the sensor on the robot
    std::vector<PairedReading> readings;
  };
  /// After a step: updates the run of rejected steps and recovers when it is long enough.
  void afterStep(const Step& step);
  /// Solves the pose from the buffered rejected readings; true when the filter took it.
  bool recover();

  std::vector<LandmarkId> used_;
  std::size_t gated_ = 0, consistent_ = 0;
  std::vector<PairedReading> paired_;  ///< this step's paired readings
  std::size_t accepted_ = 0;           ///< this step's readings that passed the gate
  std::size_t steps_ = 0, rejected_run_ = 0;
  std::deque<RejectedStep> rejected_;
  bool recovered_ = false;
};

}  // namespace budget_slam::ekf
