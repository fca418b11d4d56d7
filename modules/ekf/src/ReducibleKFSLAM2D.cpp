#include "budget_slam/ekf/ReducibleKFSLAM2D.h"

#include <mrpt/obs/CObservationBearingRange.h>

#include <stdexcept>

#include "budget_slam/ekf/MrptStepInput.h"
#include "budget_slam/gaussian/EraseRowsCols.h"

namespace budget_slam::ekf {

void ReducibleKFSLAM2D::processStep(const Step& step) {
  last_association_.clear();
  const bool mrpts_update = !usesSparseUpdate();
  iterate(mrptStepInput(step));
  if (mrpts_update) {
    // MRPT's update P <- (I - K H) P is applied to the full matrix in floating point, so P
    // drifts from symmetry by round-off; with landmarks removed and re-added every step (the
    // budget) that drift grows until P is indefinite. Keep the covariance exactly symmetric
    // after every step. A non-finite P is left as it is, for the divergence check to report at
    // this step.
    auto P = m_pkk.asEigen();
    if (P.allFinite()) P = 0.5 * (P + P.transpose()).eval();
  }
}

void ReducibleKFSLAM2D::OnGetObservationsAndDataAssociation(
    vector_KFArray_OBS& out_z, std::vector<int>& out_data_association,
    const vector_KFArray_OBS& in_all_predictions, const KFMatrix& in_S,
    const std::vector<size_t>& in_lm_indices_in_S, const KFMatrix_OxO& in_R) {
  CRangeBearingKFSLAM2D::OnGetObservationsAndDataAssociation(
      out_z, out_data_association, in_all_predictions, in_S, in_lm_indices_in_S, in_R);
  last_association_.assign(out_data_association.begin(), out_data_association.end());
}

void ReducibleKFSLAM2D::OnNewLandmarkAddedToMap(const size_t in_obsIdx,
                                                const size_t in_idxNewFeat) {
  const auto obs = m_SF->getObservationByClass<mrpt::obs::CObservationBearingRange>();
  ASSERT_(obs && in_obsIdx < obs->sensedData.size());
  mrpt::maps::CLandmark::TLandmarkID id = obs->sensedData[in_obsIdx].landmarkID;
  if (id < 0) {
    // With no removals this hands out 0, 1, 2, ... exactly as MRPT's state-index keys.
    while (m_IDs.hasKey(next_free_id_)) ++next_free_id_;
    id = next_free_id_++;
  }
  m_IDs.insert(id, static_cast<unsigned int>(in_idxNewFeat));
  m_last_data_association.newly_inserted_landmarks[in_obsIdx] = in_idxNewFeat;
  if (in_obsIdx < last_association_.size())
    last_association_[in_obsIdx] = static_cast<long>(in_idxNewFeat);
}

LandmarkId ReducibleKFSLAM2D::idAt(std::size_t state_index) const {
  mrpt::maps::CLandmark::TLandmarkID id;
  if (!m_IDs.inverse(static_cast<unsigned int>(state_index), id))
    throw std::out_of_range("no landmark at state index " + std::to_string(state_index));
  return id;
}

std::size_t ReducibleKFSLAM2D::indexOf(LandmarkId id) const {
  unsigned int idx;
  if (!m_IDs.direct(id, idx))
    throw std::out_of_range("landmark " + std::to_string(id) + " is not in the map");
  return idx;
}

void ReducibleKFSLAM2D::removeLandmark(LandmarkId id) {
  const std::size_t idx = indexOf(id);
  const std::size_t V = get_vehicle_size(), F = get_feature_size();
  const std::size_t n = static_cast<std::size_t>(m_xkk.size());
  const auto start = static_cast<Eigen::Index>(V + F * idx), k = static_cast<Eigen::Index>(F);

  // Mean and covariance: delete the landmark's F entries, rows and columns (exact
  // marginalization of a Gaussian), as the Gaussian evaluators do (gaussian/EraseRowsCols.h).
  KFVector x(n - F);
  gaussian::copyWithoutEntries(m_xkk.asEigen(), start, k, x.asEigen());
  KFMatrix P(n - F, n - F);
  gaussian::copyWithoutRowsCols(m_pkk.asEigen(), start, k, P.asEigen());
  m_xkk = std::move(x);
  m_pkk = std::move(P);

  // Ids: drop this one and shift the indices above it down by one.
  const auto old = m_IDs.getDirectMap();
  m_IDs.clear();
  for (const auto& [key, value] : old) {
    if (key == id) continue;
    m_IDs.insert(key, value > idx ? value - 1 : value);
  }
  for (auto& a : last_association_) {
    if (a == static_cast<long>(idx))
      a = -1;
    else if (a > static_cast<long>(idx))
      --a;
  }
}

void ReducibleKFSLAM2D::restore(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                                const std::vector<LandmarkId>& ids, LandmarkId next_free_id) {
  const auto n = static_cast<Eigen::Index>(3 + 2 * ids.size());
  if (mean.size() != n || cov.rows() != n || cov.cols() != n)
    throw std::invalid_argument("ReducibleKFSLAM2D::restore: sizes do not agree");
  mrpt::containers::bimap<mrpt::maps::CLandmark::TLandmarkID, unsigned int> map;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] < 0 || map.hasKey(ids[i]))
      throw std::invalid_argument("ReducibleKFSLAM2D::restore: landmark id " +
                                  std::to_string(ids[i]) + " is negative or repeated");
    map.insert(ids[i], static_cast<unsigned int>(i));
  }
  m_xkk.resize(n);
  m_xkk.asEigen() = mean;
  m_pkk.setSize(n, n);
  m_pkk.asEigen() = cov;
  m_IDs = map;
  next_free_id_ = static_cast<mrpt::maps::CLandmark::TLandmarkID>(next_free_id);
  last_association_.clear();
}

}  // namespace budget_slam::ekf
