#pragma once
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>

#include <vector>

#include "budget_slam/ekf/EkfSlamOptions.h"
#include "budget_slam/ekf/MrptStepInput.h"

namespace budget_slam::ekf {

/// MRPT's 2D range-bearing EKF (CRangeBearingKFSLAM2D: filter, motion and sensor models, data
/// association, ini sections) whose Kalman iteration is MRPT's own or the sparse one
/// ([EkfSLAM] update, EkfSlamOptions::Update). The one iteration of both filters built on it:
/// mapping (ReducibleKFSLAM2D) and relocalization in a fixed map (LocalizationKF2D), each
/// changing MRPT's behaviour only through MRPT's hooks, which both iterations call alike.
class RangeBearingKF2D : public mrpt::slam::CRangeBearingKFSLAM2D {
 public:
  /// How the Kalman update is done ([EkfSLAM] update; EkfSlamOptions::Update). Default: sparse.
  void setUpdate(EkfSlamOptions::Update update) { update_ = update; }
  EkfSlamOptions::Update update() const { return update_; }
  /// Whether the next step takes the sparse update: `update` is sparse and MRPT's options are
  /// those it covers (kfEKFNaive or kfIKFFull, analytic Jacobians, no Jacobian check).
  bool usesSparseUpdate() const;

  /// The whole state: robot (x, y, yaw), then 2 entries a landmark in state order.
  const KFVector& mean() const { return m_xkk; }
  const KFMatrix& covariance() const { return m_pkk; }

 protected:
  /// One Kalman iteration on a step's MRPT input. MRPT's update: its processActionObservation.
  /// Sparse: what processActionObservation does around MRPT's iteration (keeps the action and
  /// frame for the hooks, checks the id map, grows the simple map when asked) with
  /// runSparseIteration instead; P is then exactly symmetric (the sparse update leaves it so;
  /// the robot's and each new landmark's own block, MRPT's products H C Hᵀ, are symmetrized).
  void iterate(MrptStepInput in);

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
};

}  // namespace budget_slam::ekf
