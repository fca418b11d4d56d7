#pragma once
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>

#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Step.h"

namespace budget_slam::ekf {

/// Localization in a fixed map with MRPT's 2D range-bearing EKF: the filter, its motion and sensor
/// models, its ini sections and its data association are MRPT's CRangeBearingKFSLAM2D, unchanged;
/// what differs (docs/OUTPUTS.md, "budget-slam localize"):
///  - the state starts from a given robot pose and covariance and the map's landmarks (means and
///    marginal 2x2 covariances, no cross-covariances: a saved map keeps only the marginals);
///  - no landmark ever enters: a reading of a landmark not in the map (an unknown sensor ID, or an
///    ID-less reading MRPT's data association leaves unpaired) is not used;
///  - optionally (`gate_chi2` > 0), a paired reading whose innovation fails that chi-square gate
///    (or whose landmark MRPT does not predict in view) is not used either. Off by default, as in
///    MRPT: readings paired by sensor ID are known correspondences, and a gate rejects them as
///    soon as the filter is overconfident after a stretch without landmarks (Victoria Park's
///    stated odometry noise), which would measure the filter rather than the map;
///  - the robot pose is predicted from odometry even while no landmark is in view (MRPT's SLAM
///    filter skips prediction while its map is empty, which would freeze a robot in an empty map).
class LocalizationKF2D : public mrpt::slam::CRangeBearingKFSLAM2D {
 public:
  /// Sets the state: `start` (mean and 3x3 covariance) and `map`, whose ids become the filter's
  /// landmark IDs (ID-less readings are paired by MRPT's data association against them).
  void initialize(const PoseEstimate& start, const std::vector<LandmarkView>& map);

  /// One MRPT Kalman iteration on the step's own action and frame.
  void processStep(const Step& step);

  /// Innovation gate on d^2 = v' S^-1 v of each paired reading (13.8: chi-square, 2 degrees of
  /// freedom, 99.9%); 0 = no gate.
  double gate_chi2 = 0;

  PoseEstimate robotPose() const;
  /// The landmarks as the filter now holds them (id, mean, marginal covariance).
  std::vector<LandmarkView> landmarks() const;
  std::size_t landmarkCount() const { return getNumberOfLandmarksInTheMap(); }

  /// Per reading of the last step: the id of the map landmark it updated, or kNoLandmarkId.
  const std::vector<LandmarkId>& lastUsed() const { return used_; }
  /// Readings of the last step paired with a map landmark but rejected by the gate.
  std::size_t lastGated() const { return gated_; }
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
  std::vector<LandmarkId> used_;
  std::size_t gated_ = 0, consistent_ = 0;
};

}  // namespace budget_slam::ekf
