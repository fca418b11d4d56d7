#pragma once
#include <vector>

#include "budget_slam/core/Step.h"
#include "budget_slam/ekf/RangeBearingKF2D.h"

namespace budget_slam::ekf {

/// MRPT's 2D range-bearing EKF-SLAM (filter, motion and sensor models, data association and ini
/// sections unchanged; its Kalman iteration MRPT's or the sparse one, RangeBearingKF2D) that can
/// also drop a landmark (docs/ARCHITECTURE.md "EKF backend").
class ReducibleKFSLAM2D : public RangeBearingKF2D {
 public:
  /// One MRPT Kalman iteration on the step's own action and frame. A frame with no
  /// CObservationBearingRange is run as prediction only (MRPT itself would assert).
  void processStep(const Step& step);

  std::size_t landmarkCount() const { return getNumberOfLandmarksInTheMap(); }
  LandmarkId idAt(std::size_t state_index) const;  ///< throws std::out_of_range
  std::size_t indexOf(LandmarkId id) const;        ///< throws std::out_of_range
  bool contains(LandmarkId id) const { return m_IDs.hasKey(id); }

  /// For each reading of the last processed scan: the landmark's state index after the step,
  /// or -1 when the reading was not used.
  const std::vector<long>& lastAssociation() const { return last_association_; }

  /// Exact marginalization of landmark `id`: deletes its 2 entries of the mean, its 2 rows and
  /// columns of the covariance and its id, shifting the state indices above it.
  void removeLandmark(LandmarkId id);

  /// Puts the filter in a saved state (`run --resume`): the whole mean (robot, then landmarks),
  /// its covariance, the landmark ids in state order, and the next id for an ID-less landmark.
  /// Throws std::invalid_argument when the sizes do not agree or an id repeats.
  void restore(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
               const std::vector<LandmarkId>& ids, LandmarkId next_free_id);
  /// The next id an ID-less landmark gets (the session state keeps it).
  LandmarkId nextFreeId() const { return static_cast<LandmarkId>(next_free_id_); }

 protected:
  void OnGetObservationsAndDataAssociation(vector_KFArray_OBS& out_z,
                                           std::vector<int>& out_data_association,
                                           const vector_KFArray_OBS& in_all_predictions,
                                           const KFMatrix& in_S,
                                           const std::vector<size_t>& in_lm_indices_in_S,
                                           const KFMatrix_OxO& in_R) override;

  /// MRPT keys an ID-less landmark by its state index at insertion, which can collide after a
  /// removal; such landmarks get ids from a counter that never reuses one.
  void OnNewLandmarkAddedToMap(const size_t in_obsIdx, const size_t in_idxNewFeat) override;

 private:
  mrpt::maps::CLandmark::TLandmarkID next_free_id_ = 0;
  std::vector<long> last_association_;
};

}  // namespace budget_slam::ekf
