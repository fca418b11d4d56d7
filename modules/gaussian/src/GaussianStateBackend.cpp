#include "budget_slam/gaussian/GaussianStateBackend.h"

#include "budget_slam/gaussian/EraseRowsCols.h"

#include <stdexcept>
#include <string>

namespace budget_slam::gaussian {

GaussianStateBackend::GaussianStateBackend(std::vector<LandmarkView> landmarks, Eigen::MatrixXd P,
                                           StepIndex step)
    : landmarks_(std::move(landmarks)), P_(std::move(P)), step_(step) {
  const auto n = static_cast<Eigen::Index>(3 + 2 * landmarks_.size());
  if (P_.rows() != n || P_.cols() != n)
    throw std::invalid_argument("GaussianStateBackend: covariance is " + std::to_string(P_.rows()) +
                                "x" + std::to_string(P_.cols()) + ", expected " +
                                std::to_string(n) + " square");
  for (std::size_t i = 0; i < landmarks_.size(); ++i)
    landmarks_[i].cov = P_.block<2, 2>(3 + 2 * i, 3 + 2 * i);
}

GaussianStateBackend GaussianStateBackend::snapshot(const Backend& backend, StepIndex step) {
  auto lms = backend.landmarks();
  std::vector<VariableKey> vars = {VariableKey::pose(step)};
  for (const auto& l : lms) vars.push_back(VariableKey::landmark(l.id));
  return GaussianStateBackend(std::move(lms), backend.jointCovariance(vars), step);
}

void GaussianStateBackend::process(const Step&) {
  throw std::logic_error("GaussianStateBackend holds a frozen state; it processes no steps");
}

PoseEstimate GaussianStateBackend::robotPose() const {
  PoseEstimate p;
  p.cov = P_.topLeftCorner<3, 3>();
  return p;
}

std::size_t GaussianStateBackend::row(LandmarkId id) const {
  for (std::size_t i = 0; i < landmarks_.size(); ++i)
    if (landmarks_[i].id == id) return 3 + 2 * i;
  throw std::out_of_range("unknown landmark " + std::to_string(id));
}

void GaussianStateBackend::removeLandmark(LandmarkId id) {
  const std::size_t r = row(id);
  if (mi_) mi_->removeBlock(r);  // Schur complement, no new inverse
  eraseRowsCols(P_, static_cast<Eigen::Index>(r), 2);
  landmarks_.erase(landmarks_.begin() + static_cast<long>((r - 3) / 2));
}

std::vector<double> GaussianStateBackend::informationGain(
    const std::vector<LandmarkId>& ids) const {
  if (!mi_) mi_.emplace(P_);
  std::vector<double> out;
  out.reserve(ids.size());
  for (const LandmarkId id : ids) out.push_back(mi_->gain(row(id)));
  return out;
}

Eigen::Matrix2d GaussianStateBackend::landmarkCovariance(LandmarkId id) const {
  const auto r = static_cast<Eigen::Index>(row(id));
  return P_.block<2, 2>(r, r);
}

Eigen::MatrixXd GaussianStateBackend::jointCovariance(const std::vector<VariableKey>& vars) const {
  std::vector<Eigen::Index> rows;
  for (const auto& v : vars) {
    if (v.kind == VariableKey::Kind::Pose) {
      if (static_cast<StepIndex>(v.id) != step_)
        throw std::invalid_argument("the state holds only the pose of step " +
                                    std::to_string(step_));
      for (Eigen::Index k = 0; k < 3; ++k) rows.push_back(k);
    } else {
      const auto r = static_cast<Eigen::Index>(row(v.id));
      rows.push_back(r);
      rows.push_back(r + 1);
    }
  }
  Eigen::MatrixXd out(rows.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < rows.size(); ++j) out(i, j) = P_(rows[i], rows[j]);
  return out;
}

}  // namespace budget_slam::gaussian
