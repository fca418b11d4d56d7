#include "budget_slam/ekf/EkfBackend.h"

#include <algorithm>
#include <stdexcept>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/ekf/MrptIniCheck.h"

namespace budget_slam::ekf {

EkfBackend::EkfBackend(const mrpt::config::CConfigFileBase& ini) {
  checkMrptKfSlamOptions(ini);  // MRPT takes any number and dumps a stack on a bad enum
  try {
    kf_.loadOptions(ini);  // exactly what MRPT's kf-slam does
  } catch (const std::exception& e) {
    throw ConfigError("[RangeBearingKFSLAM]: MRPT cannot load the filter options: " +
                      exceptionLine(e));
  }
  kf_.KF_options.verbosity_level = mrpt::system::LVL_ERROR;
  EkfSlamOptions options;
  options.loadFromConfigFile(ini, EkfSlamOptions::kSection);
  kf_.setUpdate(options.update);
}

std::unique_ptr<Backend> EkfBackend::clone() const { return std::make_unique<EkfBackend>(*this); }

void EkfBackend::process(const Step& step) {
  mi_.reset();
  kf_.processStep(step);
  last_step_ = step.index;

  const auto& x = kf_.mean();
  const Eigen::Vector2d robot(x[0], x[1]);
  const auto& assoc = kf_.lastAssociation();
  last_ids_.assign(assoc.size(), kNoLandmarkId);
  for (std::size_t r = 0; r < assoc.size(); ++r) {
    const long idx = assoc[r];
    if (idx < 0) continue;
    const LandmarkId id = kf_.idAt(static_cast<std::size_t>(idx));
    last_ids_[r] = id;
    tracks_.addSighting(id, robot, step.index);  // Hochdorfer & Schlegel Eq. 2
  }
  if (!keep_trajectory_) trajectory_.clear();
  trajectory_.push_back({step.index, step.t, Pose2(x[0], x[1], x[2])});
}

std::vector<LandmarkId> EkfBackend::idsInStateOrder() const {
  std::vector<LandmarkId> ids(kf_.landmarkCount());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = kf_.idAt(i);
  return ids;
}

std::vector<LandmarkView> EkfBackend::landmarks() const {
  const auto& x = kf_.mean();
  const auto& P = kf_.covariance().asEigen();
  std::vector<LandmarkView> out;
  out.reserve(kf_.landmarkCount());
  for (std::size_t i = 0; i < kf_.landmarkCount(); ++i) {
    LandmarkView v;
    v.id = kf_.idAt(i);
    const Eigen::Index r = static_cast<Eigen::Index>(3 + 2 * i);
    v.mean = Eigen::Vector2d(x[r], x[r + 1]);
    v.cov = P.block<2, 2>(r, r);
    if (const LandmarkTrack* t = tracks_.find(v.id)) t->describe(&v);
    out.push_back(v);
  }
  return out;
}

std::vector<LandmarkId> EkfBackend::observedAt(StepIndex step) const {
  return tracks_.observedAt(step);
}

PoseEstimate EkfBackend::robotPose() const {
  const auto& x = kf_.mean();
  PoseEstimate p;
  p.mean = Pose2(x[0], x[1], x[2]);
  p.cov = kf_.covariance().asEigen().block<3, 3>(0, 0);
  return p;
}

void EkfBackend::removeLandmark(LandmarkId id) {
  const std::size_t row = stateRow(id);  // throws if unknown
  if (mi_) mi_->removeBlock(row);
  kf_.removeLandmark(id);
  tracks_.erase(id);
}

std::vector<double> EkfBackend::informationGain(const std::vector<LandmarkId>& ids) const {
  if (!mi_) try {
      mi_.emplace(kf_.covariance().asEigen());
    } catch (const gaussian::BlockMutualInformation::NotPositiveDefinite&) {
      // A property of the data and the filter's numerics (e.g. sensor noise far below what the
      // readings carry), not of the program: a one-line error naming the step.
      throw Error("step " + std::to_string(last_step_) +
                  ": the ekf filter's covariance lost positive definiteness, so the mutual "
                  "information of its landmarks is undefined");
    }
  std::vector<double> out;
  out.reserve(ids.size());
  for (const LandmarkId id : ids) out.push_back(mi_->gain(stateRow(id)));
  return out;
}

Eigen::Matrix2d EkfBackend::landmarkCovariance(LandmarkId id) const {
  const auto r = static_cast<Eigen::Index>(stateRow(id));
  return kf_.covariance().asEigen().block<2, 2>(r, r);
}

Eigen::MatrixXd EkfBackend::jointCovariance(const std::vector<VariableKey>& vars) const {
  std::vector<Eigen::Index> rows;
  for (const auto& v : vars) {
    if (v.kind == VariableKey::Kind::Pose) {
      if (static_cast<StepIndex>(v.id) != last_step_)
        throw std::invalid_argument("the EKF holds only the latest pose (step " +
                                    std::to_string(last_step_) + ")");
      for (Eigen::Index k = 0; k < 3; ++k) rows.push_back(k);
    } else {
      const auto r = static_cast<Eigen::Index>(stateRow(v.id));
      rows.push_back(r);
      rows.push_back(r + 1);
    }
  }
  const auto& P = kf_.covariance().asEigen();
  Eigen::MatrixXd out(rows.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < rows.size(); ++j) out(i, j) = P(rows[i], rows[j]);
  return out;
}

void EkfBackend::saveSession(session::SessionState& state) const {
  const auto& P = kf_.covariance().asEigen();
  const Eigen::Index m = P.rows() - 3;
  state.map.landmarks = landmarks();
  state.map.covariance = P.bottomRightCorner(m, m);
  session::RobotBlock robot;
  robot.pose = robotPose();
  robot.cross_covariance = P.topRightCorner(3, m);
  state.robot = robot;
  session::SessionSection& s = state.section("backend.ekf");
  s.putInteger("next_free_id", kf_.nextFreeId());
  s.putInteger("last_step", static_cast<std::int64_t>(last_step_));
}

void EkfBackend::restoreSession(const session::SessionState& state) {
  const session::SessionSection& s = state.take("backend.ekf");
  const auto& lm = state.map.landmarks;
  const auto n = static_cast<Eigen::Index>(3 + 2 * lm.size());
  Eigen::VectorXd x(n);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(n, n);
  std::vector<LandmarkId> ids;
  for (std::size_t i = 0; i < lm.size(); ++i) {
    ids.push_back(lm[i].id);
    x.segment<2>(3 + 2 * static_cast<Eigen::Index>(i)) = lm[i].mean;
  }
  P.bottomRightCorner(n - 3, n - 3) = state.map.covariance;
  const PoseEstimate pose = state.robot ? state.robot->pose : robotPose();
  x.head<3>() = Eigen::Vector3d(pose.mean.x, pose.mean.y, pose.mean.phi);
  P.topLeftCorner<3, 3>() = pose.cov;
  if (state.robot) {
    P.topRightCorner(3, n - 3) = state.robot->cross_covariance;
    P.bottomLeftCorner(n - 3, 3) = state.robot->cross_covariance.transpose();
  }
  const LandmarkId next = s.integer("next_free_id", 0);
  last_step_ = static_cast<StepIndex>(s.integer("last_step", 0));
  try {
    kf_.restore(x, P, ids, next);
  } catch (const std::invalid_argument& e) {
    s.failSection(e.what());
  }
  tracks_ = LandmarkTracks();
  for (const auto& l : lm) tracks_.restore(l);
  trajectory_.clear();
  mi_.reset();
  last_ids_.clear();
}

}  // namespace budget_slam::ekf
