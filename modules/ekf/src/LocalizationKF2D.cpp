#include "budget_slam/ekf/LocalizationKF2D.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <limits>
#include <set>
#include <stdexcept>

#include "budget_slam/core/MrptPose.h"
#include "budget_slam/core/RangeBearingModel.h"
#include "budget_slam/ekf/MrptStepInput.h"
#include "budget_slam/ekf/PoseFromPoints.h"

namespace budget_slam::ekf {

void LocalizationKF2D::initialize(const PoseEstimate& start, const std::vector<LandmarkView>& map) {
  const std::size_t n = 3 + 2 * map.size();
  m_xkk.resize(n);
  m_pkk.setSize(n, n);
  m_pkk.setZero();
  m_xkk[0] = start.mean.x;
  m_xkk[1] = start.mean.y;
  m_xkk[2] = mrpt::math::wrapToPi(start.mean.phi);
  auto P = m_pkk.asEigen();
  P.block<3, 3>(0, 0) = start.cov;
  m_IDs.clear();
  for (std::size_t i = 0; i < map.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(3 + 2 * i);
    m_xkk[r] = map[i].mean.x();
    m_xkk[r + 1] = map[i].mean.y();
    P.block<2, 2>(r, r) = map[i].cov;
    if (m_IDs.hasKey(map[i].id))
      throw std::invalid_argument("landmark id " + std::to_string(map[i].id) + " twice in the map");
    m_IDs.insert(map[i].id, static_cast<unsigned int>(i));
  }
  used_.clear();
  gated_ = 0;
  paired_.clear();
  accepted_ = 0;
  steps_ = rejected_run_ = 0;
  rejected_.clear();
  recovered_ = false;
}

void LocalizationKF2D::processStep(const Step& step) {
  used_.clear();
  gated_ = 0;
  paired_.clear();
  accepted_ = 0;
  recovered_ = false;
  iterate(mrptStepInput(step));
  afterStep(step);
}

void LocalizationKF2D::afterStep(const Step& step) {
  ++steps_;
  if (paired_.empty()) return;  // nothing read of the map: the run neither grows nor breaks
  if (accepted_ > 0) {
    rejected_run_ = 0;
    rejected_.clear();
    return;
  }
  ++rejected_run_;
  if (gate.recover_after_steps == 0) return;
  const auto& s = step.scan->sensor_pose_on_robot;
  rejected_.push_back({steps_, robotPose().mean, Pose2(s.x, s.y, s.yaw), paired_});
  while (!rejected_.empty() && steps_ - rejected_.front().step >= gate.recovery_window_steps)
    rejected_.pop_front();
  if (rejected_run_ >= gate.recover_after_steps && recover()) {
    rejected_run_ = 0;
    rejected_.clear();
    recovered_ = true;
  }
}

bool LocalizationKF2D::recover() {
  // Each rejected reading where it puts its landmark in the current robot frame: its own robot
  // frame, then the filter's motion from that step to now (x_now (-) x_then (+) q).
  const mrpt::poses::CPose2D now(toTPose2D(robotPose().mean));
  const auto& P = m_pkk.asEigen();
  std::vector<PointMatch> matches;
  for (const RejectedStep& r : rejected_) {
    const mrpt::poses::CPose2D relative = mrpt::poses::CPose2D(toTPose2D(r.robot)) - now;
    const double c = std::cos(relative.phi()), s = std::sin(relative.phi());
    Eigen::Matrix2d rot;
    rot << c, -s, s, c;
    for (const PairedReading& p : r.readings) {
      // The reading's Cartesian covariance: polar noise through d(point)/d(range, bearing).
      Eigen::Matrix2d J;
      const Eigen::Vector2d q = readingPoint(p.range, p.bearing, r.sensor, nullptr, &J);
      const Eigen::Matrix2d R = Eigen::Vector2d(mrpt::square(options.std_sensor_range),
                                                mrpt::square(options.std_sensor_yaw))
                                    .asDiagonal();
      PointMatch m;
      m.in_robot = Eigen::Vector2d(relative.x(), relative.y()) + rot * q;
      m.cov_in_robot = rot * J * R * J.transpose() * rot.transpose();
      const auto k = static_cast<Eigen::Index>(3 + 2 * p.landmark);
      m.in_map = Eigen::Vector2d(m_xkk[k], m_xkk[k + 1]);
      m.cov_in_map = P.block<2, 2>(k, k);
      matches.push_back(m);
    }
  }
  std::set<std::size_t> distinct;
  for (const RejectedStep& r : rejected_)
    for (const PairedReading& p : r.readings) distinct.insert(p.landmark);
  if (distinct.size() < std::max<std::size_t>(2, gate.recovery_min_landmarks)) return false;
  const auto fit = fitPose(matches);
  if (!fit || fit->worst_d2 > gate.chi2) return false;
  m_xkk[0] = fit->pose.mean.x;
  m_xkk[1] = fit->pose.mean.y;
  m_xkk[2] = fit->pose.mean.phi;
  auto Pw = m_pkk.asEigen();
  Pw.topRows<3>().setZero();
  Pw.leftCols<3>().setZero();
  Pw.block<3, 3>(0, 0) = 0.5 * (fit->pose.cov + fit->pose.cov.transpose());
  return true;
}

PoseEstimate LocalizationKF2D::robotPose() const {
  PoseEstimate p;
  p.mean = Pose2(m_xkk[0], m_xkk[1], m_xkk[2]);
  p.cov = m_pkk.asEigen().block<3, 3>(0, 0);
  return p;
}

std::vector<LandmarkView> LocalizationKF2D::landmarks() const {
  std::vector<LandmarkView> out(landmarkCount());
  const auto& P = m_pkk.asEigen();
  for (std::size_t i = 0; i < out.size(); ++i) {
    mrpt::maps::CLandmark::TLandmarkID id;
    if (!m_IDs.inverse(static_cast<unsigned int>(i), id))
      throw std::logic_error("localization filter: no id at state index " + std::to_string(i));
    const auto r = static_cast<Eigen::Index>(3 + 2 * i);
    out[i].id = id;
    out[i].mean = Eigen::Vector2d(m_xkk[r], m_xkk[r + 1]);
    out[i].cov = P.block<2, 2>(r, r);
  }
  return out;
}

void LocalizationKF2D::OnTransitionModel(const KFArray_ACT& in_u, KFArray_VEH& inout_x,
                                         bool& out_skipPrediction) const {
  // MRPT's composition x (+) u, done even with no landmark in the state.
  const mrpt::poses::CPose2D p = mrpt::poses::CPose2D(inout_x[0], inout_x[1], inout_x[2]) +
                                 mrpt::poses::CPose2D(in_u[0], in_u[1], in_u[2]);
  inout_x[0] = p.x();
  inout_x[1] = p.y();
  inout_x[2] = p.phi();
  out_skipPrediction = false;
}

void LocalizationKF2D::OnGetObservationsAndDataAssociation(
    vector_KFArray_OBS& out_z, std::vector<int>& out_data_association,
    const vector_KFArray_OBS& in_all_predictions, const KFMatrix& in_S,
    const std::vector<size_t>& in_lm_indices_in_S, const KFMatrix_OxO& in_R) {
  // MRPT's own readings and pairing (by sensor ID, else its data association)...
  vector_KFArray_OBS z;
  std::vector<int> da;
  CRangeBearingKFSLAM2D::OnGetObservationsAndDataAssociation(z, da, in_all_predictions, in_S,
                                                             in_lm_indices_in_S, in_R);
  // ... then only the paired readings that pass the gate go to the update; the rest (unpaired:
  // -1, which MRPT would turn into new landmarks) are left out altogether.
  used_.assign(z.size(), kNoLandmarkId);
  gated_ = consistent_ = 0;
  paired_.clear();
  accepted_ = 0;
  out_z.clear();
  out_data_association.clear();
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (da[i] < 0) continue;
    const auto lm = static_cast<std::size_t>(da[i]);
    paired_.push_back({lm, z[i][0], z[i][1]});
    const auto it = std::find(in_lm_indices_in_S.begin(), in_lm_indices_in_S.end(), lm);
    // d^2 = v' S^-1 v of the reading against the map's landmark; infinite when MRPT predicts the
    // landmark out of view (far off) or S is not positive definite.
    double d2 = std::numeric_limits<double>::infinity();
    if (it != in_lm_indices_in_S.end()) {
      const auto k = static_cast<Eigen::Index>(2 * (it - in_lm_indices_in_S.begin()));
      const Eigen::Matrix2d S = in_S.asEigen().block<2, 2>(k, k);
      const Eigen::Vector2d v(z[i][0] - in_all_predictions[lm][0],
                              mrpt::math::wrapToPi(z[i][1] - in_all_predictions[lm][1]));
      const Eigen::LLT<Eigen::Matrix2d> llt(S);
      if (llt.info() == Eigen::Success) d2 = v.dot(llt.solve(v));
    }
    if (d2 <= kConsistentChi2) ++consistent_;
    if (gate.chi2 > 0 && !(d2 <= gate.chi2)) {
      ++gated_;
      continue;
    }
    ++accepted_;
    out_z.push_back(z[i]);
    out_data_association.push_back(da[i]);
    mrpt::maps::CLandmark::TLandmarkID id;
    if (m_IDs.inverse(static_cast<unsigned int>(lm), id)) used_[i] = id;
  }
}

void LocalizationKF2D::OnNewLandmarkAddedToMap(const size_t, const size_t) {
  throw std::logic_error("localization filter: a landmark was about to enter the map");
}

}  // namespace budget_slam::ekf
