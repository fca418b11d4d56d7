#pragma once
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>

#include <vector>

#include "budget_slam/core/Step.h"
#include "budget_slam/ekf/EkfSlamOptions.h"

namespace budget_slam::ekf {

/// MRPT's 2D range-bearing EKF-SLAM (filter, motion and sensor models, data association and ini
/// sections unchanged) that can also drop a landmark (docs/ARCHITECTURE.md "EKF backend").
class ReducibleKFSLAM2D : public mrpt::slam::CRangeBearingKFSLAM2D {
 public:
  /// One MRPT Kalman iteration on the step's own action and frame. A frame with no
  /// CObservationBearingRange is run as prediction only (MRPT itself would assert).
  void processStep(const Step& step);

  /// How the Kalman update is done ([EkfSLAM] update; EkfSlamOptions::Update). Default: sparse.
  void setUpdate(EkfSlamOptions::Update update) { update_ = update; }
  EkfSlamOptions::Update update() const { return update_; }
  /// Whether the next step takes the sparse update: `update` is sparse and MRPT's options are
  /// those it covers (kfEKFNaive or kfIKFFull, analytic Jacobians, no Jacobian check).
  bool usesSparseUpdate() const;

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

  const KFVector& mean() const { return m_xkk; }
  const KFMatrix& covariance() const { return m_pkk; }

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
  /// MRPT's Kalman iteration (CKalmanFilterCapable::runOneKalmanIteration: prediction, predicted
  /// readings, Jacobians, innovation covariance, data association, update, new landmarks) through
  /// the same hooks, with the update of sparseKalmanUpdate (src/SparseKalmanIteration.cpp).
  void runSparseIteration();
  /// MRPT's innovation covariance of the predicted landmarks, S = H P Hᵀ + R from the 2 x 2
  /// blocks of each pair (as runOneKalmanIteration builds it for the data association).
  KFMatrix innovationCovariance(const std::vector<size_t>& predicted,
                                const std::vector<KFMatrix_OxV>& Hx,
                                const std::vector<KFMatrix_OxF>& Hy, const KFMatrix_OxO& R) const;

  /// The readings associated with no landmark (-1) become landmarks at the end of the state, as
  /// MRPT's detail::addNewLandmarks makes them, with P reallocated once for all of them.
  void addNewLandmarks(const vector_KFArray_OBS& Z, const std::vector<int>& association,
                       const KFMatrix_OxO& R);

  EkfSlamOptions::Update update_ = EkfSlamOptions::Update::Sparse;
  mrpt::maps::CLandmark::TLandmarkID next_free_id_ = 0;
  std::vector<long> last_association_;
};

}  // namespace budget_slam::ekf
