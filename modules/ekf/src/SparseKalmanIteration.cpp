// The Kalman iteration of RangeBearingKF2D (the mapping filter ReducibleKFSLAM2D and the
// relocalization filter LocalizationKF2D) with the sparse update ([EkfSLAM] update = sparse).
//
// MRPT's CKalmanFilterCapable::runOneKalmanIteration (MRPT 2.5) does its update with the
// observation Jacobian of the whole state as a dense matrix and P <- (I - K H) P: an n x n
// product with an n x n matrix, O(n³) a step (n = 3 + 2 landmarks), which is nearly all of a
// large map's run time (docs/PERFORMANCE.md "EKF update"). This iteration calls the same hooks
// of CRangeBearingKFSLAM2D in the same order (motion model, predicted readings, which landmarks
// to predict, Jacobians, innovation covariance, data association and its re-prediction of
// missed landmarks, new landmarks) and replaces only the update by sparseKalmanUpdate; new
// landmarks are inserted with MRPT's formulas into a covariance grown once a step.
#include <mrpt/math/ops_matrices.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <algorithm>
#include <numeric>

#include "budget_slam/ekf/RangeBearingKF2D.h"
#include "budget_slam/ekf/SparseKalmanUpdate.h"

namespace budget_slam::ekf {

using mrpt::bayes::kfEKFNaive;
using mrpt::bayes::kfIKFFull;

namespace {

/// Replaces the square block of P at (start, start) by the mean of it and its transpose.
void symmetrizeBlock(Eigen::Ref<RowMajorMatrix> P, Eigen::Index start, Eigen::Index size) {
  for (Eigen::Index i = start; i < start + size; ++i)
    for (Eigen::Index j = start; j < i; ++j) P(i, j) = P(j, i) = 0.5 * (P(i, j) + P(j, i));
}

}  // namespace

bool RangeBearingKF2D::usesSparseUpdate() const {
  const auto& o = KF_options;
  return update_ == EkfSlamOptions::Update::Sparse &&
         (o.method == kfEKFNaive || o.method == kfIKFFull) && o.use_analytic_transition_jacobian &&
         o.use_analytic_observation_jacobian && !o.debug_verify_analytic_jacobians;
}

void RangeBearingKF2D::iterate(MrptStepInput in) {
  if (!usesSparseUpdate()) {
    processActionObservation(in.action, in.frame);
    return;
  }
  // What MRPT's processActionObservation does around its iteration.
  m_action = in.action;
  m_SF = in.frame;
  ASSERT_(m_IDs.size() == getNumberOfLandmarksInTheMap());
  const auto n_before = static_cast<Eigen::Index>(m_xkk.size());
  runSparseIteration();
  if (options.create_simplemap) {
    auto pose = std::make_shared<mrpt::poses::CPosePDFGaussian>();
    getCurrentRobotPose(*pose);
    m_SFs.insert(pose, in.frame);
  }
  // The sparse update leaves P exactly symmetric; only the blocks MRPT computes as products
  // H C Hᵀ may not be: the robot's (a prediction-only step) and each new landmark's own.
  auto P = m_pkk.asEigen();
  symmetrizeBlock(P, 0, 3);
  for (Eigen::Index r = n_before; r < P.rows(); r += 2) symmetrizeBlock(P, r, 2);
}

RangeBearingKF2D::KFMatrix RangeBearingKF2D::innovationCovariance(
    const std::vector<size_t>& predicted, const std::vector<KFMatrix_OxV>& Hx,
    const std::vector<KFMatrix_OxF>& Hy, const KFMatrix_OxO& R) const {
  const auto P = m_pkk.asEigen();
  const std::size_t N = predicted.size();
  KFMatrix S(2 * N, 2 * N);
  auto s = S.asEigen();
  const Eigen::Matrix3d Px = P.block<3, 3>(0, 0);
  for (std::size_t i = 0; i < N; ++i) {
    const Eigen::Index ri = static_cast<Eigen::Index>(3 + 2 * predicted[i]);
    const auto Pyix = P.block<2, 3>(ri, 0);
    for (std::size_t j = i; j < N; ++j) {
      const Eigen::Index rj = static_cast<Eigen::Index>(3 + 2 * predicted[j]);
      const auto Pxyj = P.block<3, 2>(0, rj);
      const auto Pyiyj = P.block<2, 2>(ri, rj);
      const auto& hxi = Hx[i].asEigen();
      const auto& hyi = Hy[i].asEigen();
      const auto& hxj = Hx[j].asEigen();
      const auto& hyj = Hy[j].asEigen();
      // The four terms in MRPT's order: robot-robot, landmark i-robot, robot-landmark j, landmarks.
      const Eigen::Matrix2d Sij = hxi * Px * hxj.transpose() + hyi * Pyix * hxj.transpose() +
                                  hxi * Pxyj * hyj.transpose() + hyi * Pyiyj * hyj.transpose();
      const auto a = static_cast<Eigen::Index>(2 * i), b = static_cast<Eigen::Index>(2 * j);
      s.block<2, 2>(a, b) = Sij;
      if (i != j) s.block<2, 2>(b, a) = Sij.transpose();
    }
    const auto a = static_cast<Eigen::Index>(2 * i);
    s.block<2, 2>(a, a) += R.asEigen();
  }
  return S;
}

void RangeBearingKF2D::runSparseIteration() {
  // 1-4. Prediction: the robot's mean, its covariance block and its cross-covariances, O(n).
  KFArray_ACT u;
  OnGetAction(u);
  const std::size_t n_map = getNumberOfLandmarksInTheMap();
  {
    auto P = m_pkk.asEigen();
    KFArray_VEH xv(&m_xkk[0]);
    bool skip_prediction = false;
    OnTransitionModel(u, xv, skip_prediction);
    if (!skip_prediction) {
      KFMatrix_VxV F;
      OnTransitionJacobian(F);
      KFMatrix_VxV Q;
      OnTransitionNoise(Q);
      const Eigen::Matrix3d Pxx = P.block<3, 3>(0, 0);
      P.block<3, 3>(0, 0) = Q.asEigen() + F.asEigen() * Pxx * F.asEigen().transpose();
      for (std::size_t i = 0; i < n_map; ++i) {
        const auto c = static_cast<Eigen::Index>(3 + 2 * i);
        const Eigen::Matrix<double, 3, 2> aux = F.asEigen() * P.block<3, 2>(0, c);
        P.block<3, 2>(0, c) = aux;
        P.block<2, 3>(c, 0) = aux.transpose();
      }
      for (std::size_t k = 0; k < 3; ++k) m_xkk[k] = xv[k];
      OnNormalizeStateVector();
    }
  }

  // 5. The predicted reading of every landmark; which of them get a covariance.
  KFMatrix_OxO R;
  OnGetObservationNoise(R);
  std::vector<size_t> all(n_map);
  std::iota(all.begin(), all.end(), std::size_t{0});
  vector_KFArray_OBS predictions;
  OnObservationModel(all, predictions);
  std::vector<size_t> predicted;
  OnPreComputingPredictions(predictions, predicted);

  // 6. Jacobians and innovation covariance of the predicted landmarks, data association. As in
  // MRPT, a reading associated with a landmark left out of the prediction adds it and repeats.
  std::vector<KFMatrix_OxV> Hx;
  std::vector<KFMatrix_OxF> Hy;
  KFMatrix S;
  vector_KFArray_OBS Z;
  std::vector<int> association;
  std::vector<size_t> missing;
  do {
    predicted.insert(predicted.end(), missing.begin(), missing.end());
    missing.clear();
    for (std::size_t i = Hx.size(); i < predicted.size(); ++i) {
      Hx.emplace_back();
      Hy.emplace_back();
      OnObservationJacobians(predicted[i], Hx.back(), Hy.back());
    }
    S = innovationCovariance(predicted, Hx, Hy, R);
    Z.clear();
    OnGetObservationsAndDataAssociation(Z, association, predictions, S, predicted, R);
    for (const int a : association)
      if (a >= 0 &&
          mrpt::containers::find_in_vector(static_cast<size_t>(a), predicted) == std::string::npos)
        missing.push_back(static_cast<size_t>(a));
  } while (!missing.empty());

  // 7. The update, from the rows of H that are not zero.
  std::vector<ReadingJacobian> H;
  std::vector<size_t> rows_of_S;
  std::vector<double> innovation;
  for (std::size_t r = 0; r < association.size() && r < Z.size(); ++r) {
    if (association[r] < 0) continue;
    const auto lm = static_cast<size_t>(association[r]);
    const std::size_t p = mrpt::containers::find_in_vector(lm, predicted);
    H.push_back({Hx[p].asEigen(), Hy[p].asEigen(), static_cast<Eigen::Index>(3 + 2 * lm)});
    rows_of_S.push_back(2 * p);
    rows_of_S.push_back(2 * p + 1);
    KFArray_OBS nu = Z[r];
    OnSubstractObservationVectors(nu, predictions[lm]);
    innovation.push_back(nu[0]);
    innovation.push_back(nu[1]);
  }
  if (!H.empty()) {
    KFMatrix S_observed;
    mrpt::math::extractSubmatrixSymmetrical(S, rows_of_S, S_observed);
    const Eigen::MatrixXd S_inverse = S_observed.inverse_LLt().asEigen();
    const int iterations = KF_options.method == kfIKFFull ? KF_options.IKF_iterations : 1;
    sparseKalmanUpdate(m_pkk.asEigen(), m_xkk.asEigen(), H, S_inverse,
                       Eigen::Map<const Eigen::VectorXd>(
                           innovation.data(), static_cast<Eigen::Index>(innovation.size())),
                       iterations);
  }
  OnNormalizeStateVector();

  // 8. New landmarks.
  addNewLandmarks(Z, association, R);
  OnPostIteration();
}

void RangeBearingKF2D::addNewLandmarks(const vector_KFArray_OBS& Z,
                                       const std::vector<int>& association, const KFMatrix_OxO& R) {
  const auto added = static_cast<std::size_t>(
      std::count_if(association.begin(), association.end(), [](int a) { return a < 0; }));
  if (added == 0) return;
  // One reallocation of P for all of them: growing a dense matrix copies it whole (and touches
  // fresh memory), which MRPT's detail::addNewLandmarks does once a landmark.
  const std::size_t n0 = m_xkk.size(), n = n0 + 2 * added;
  m_xkk.resize(n);
  m_pkk.setSize(n, n);
  auto P = m_pkk.asEigen();
  const Eigen::Matrix3d Pxx = P.block<3, 3>(0, 0);
  std::size_t row = n0;
  for (std::size_t r = 0; r < association.size() && r < Z.size(); ++r) {
    if (association[r] >= 0) continue;
    // MRPT's insertion, the same terms: the inverse sensor model y(x, z) and its Jacobians, the
    // cross-covariance with the robot and every earlier landmark (this step's included), and
    // the landmark's own block from the robot's and the reading's uncertainty.
    // (CRangeBearingKFSLAM2D has the 4-argument model only: the reading's noise enters through
    // dyn_dhn, as the base class's 6-argument form then says.)
    KFArray_FEAT yn;
    KFMatrix_FxV dyn_dxv;
    KFMatrix_FxO dyn_dhn;
    OnInverseObservationModel(Z[r], yn, dyn_dxv, dyn_dhn);
    OnNewLandmarkAddedToMap(r, (row - 3) / 2);
    m_xkk[row] = yn[0];
    m_xkk[row + 1] = yn[1];
    const auto i = static_cast<Eigen::Index>(row);
    const Eigen::Matrix<double, 2, 3> Pyx = dyn_dxv.asEigen() * Pxx;
    P.block<2, 3>(i, 0) = Pyx;
    P.block<3, 2>(0, i) = Pyx.transpose();
    for (Eigen::Index q = 3; q < i; q += 2) {
      const Eigen::Matrix2d cross = dyn_dxv.asEigen() * P.block<3, 2>(0, q);
      P.block<2, 2>(i, q) = cross;
      P.block<2, 2>(q, i) = cross.transpose();
    }
    P.block<2, 2>(i, i) = dyn_dxv.asEigen() * Pxx * dyn_dxv.asEigen().transpose() +
                          dyn_dhn.asEigen() * R.asEigen() * dyn_dhn.asEigen().transpose();
    row += 2;
  }
}

}  // namespace budget_slam::ekf
