#pragma once
#include <algorithm>
#include <stdexcept>

#include "budget_slam/core/Backend.h"

namespace budget_slam::testing {

/// A backend holding a fixed list of landmark views, for reducer tests without a filter.
class FakeBackend : public Backend {
 public:
  explicit FakeBackend(std::vector<LandmarkView> lms) : lms_(std::move(lms)) {}
  std::string name() const override { return "fake"; }
  void process(const Step&) override {}
  std::vector<LandmarkView> landmarks() const override { return lms_; }
  std::size_t landmarkCount() const override { return lms_.size(); }
  PoseEstimate robotPose() const override { return {pose, Eigen::Matrix3d::Identity()}; }
  std::vector<TrajectoryPoint> trajectory() const override { return {}; }
  std::size_t poseCount() const override { return 1; }
  void removeLandmark(LandmarkId id) override {
    const auto it = std::find_if(lms_.begin(), lms_.end(), [&](auto& l) { return l.id == id; });
    if (it == lms_.end()) throw std::out_of_range("unknown landmark");
    lms_.erase(it);
  }
  std::vector<double> informationGain(const std::vector<LandmarkId>& ids) const override {
    std::vector<double> out;
    for (auto id : ids) out.push_back(gains.count(id) ? gains.at(id) : 0.0);
    return out;
  }
  Eigen::Matrix2d landmarkCovariance(LandmarkId id) const override {
    for (const auto& l : lms_)
      if (l.id == id) return l.cov;
    throw std::out_of_range("unknown landmark");
  }
  Eigen::MatrixXd jointCovariance(const std::vector<VariableKey>&) const override {
    throw std::invalid_argument("not in the fake");
  }
  void add(const LandmarkView& l) { lms_.push_back(l); }
  bool has(LandmarkId id) const {
    return std::any_of(lms_.begin(), lms_.end(), [&](auto& l) { return l.id == id; });
  }
  /// Landmark `id` observed at `step` (a sighting more, last seen now).
  void see(LandmarkId id, StepIndex step) {
    for (auto& l : lms_)
      if (l.id == id) {
        l.last_step = step;
        ++l.n_obs;
      }
  }
  std::map<LandmarkId, double> gains;
  Pose2 pose;  ///< what robotPose() reports

 private:
  std::vector<LandmarkView> lms_;
};

inline LandmarkView landmark(LandmarkId id, double sxx, double syy, StepIndex first, StepIndex last,
                             double ox = 0, double oy = 0) {
  LandmarkView v;
  v.id = id;
  v.cov << sxx, 0, 0, syy;
  v.first_step = first;
  v.last_step = last;
  v.n_obs = 1;
  v.obs_mean = Eigen::Vector2d(ox, oy);
  return v;
}

}  // namespace budget_slam::testing
