#include "budget_slam/wakeup/ReadingWindow.h"

#include <cmath>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/RangeBearingModel.h"

namespace budget_slam::wakeup {

ReadingWindow::ReadingWindow(const ReadingNoise& noise, const WakeUpOptions& options)
    : noise_(noise), options_(options) {}

StepIndex ReadingWindow::latest() const { return steps_.empty() ? 0 : steps_.back().index; }

void ReadingWindow::add(const Step& step) {
  Gathered g;
  g.index = step.index;
  if (step.odometry) {
    g.odometry = step.odometry->mean;
    g.odometry_cov = step.odometry->cov;
  } else {
    const double sxy = options_.no_odometry_std_xy;
    const double syaw = options_.no_odometry_std_yaw_deg * M_PI / 180;
    g.odometry_cov = Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal();
  }
  if (step.scan) {
    const auto& p = step.scan->sensor_pose_on_robot;
    g.sensor = Pose2(p.x, p.y, p.yaw);
    g.scanned = true;
    g.min_range = step.scan->min_range;
    g.max_range = step.scan->max_range;
    g.fov = step.scan->fov_yaw;
    for (const auto& r : step.scan->readings)
      if (std::isfinite(r.range) && std::isfinite(r.yaw) && r.range > 0) g.readings.push_back(r);
    max_range_ = std::max(max_range_, step.scan->max_range);
  }
  steps_.push_back(std::move(g));
}

std::vector<std::pair<Pose2, Eigen::Matrix3d>> ReadingWindow::chain() const {
  std::vector<std::pair<Pose2, Eigen::Matrix3d>> out(steps_.size());
  // E: the robot at step k in the latest frame; from k to k-1 through the inverse of step k's
  // odometry: X_{k-1} = X_k (+) (-)u_k.
  Pose2 E;
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  for (std::size_t k = steps_.size(); k-- > 0;) {
    out[k] = {E, P};
    Eigen::Matrix3d Jinv, Ja, Jb;
    const Pose2 inv = steps_[k].odometry.inverse(&Jinv);
    E = compose(E, inv, &Ja, &Jb);
    const Eigen::Matrix3d Ju = Jb * Jinv;
    P = Ja * P * Ja.transpose() + Ju * steps_[k].odometry_cov * Ju.transpose();
  }
  return out;
}

std::vector<LocalReading> ReadingWindow::readings() const {
  const Eigen::Matrix2d R =
      Eigen::Vector2d(noise_.std_range * noise_.std_range, noise_.std_bearing * noise_.std_bearing)
          .asDiagonal();
  const auto poses = chain();
  std::vector<LocalReading> out;
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    const Gathered& g = steps_[k];
    Eigen::Matrix3d Js;
    const Pose2 sensor = compose(poses[k].first, g.sensor, &Js, nullptr);
    const Eigen::Matrix3d sensor_cov = Js * poses[k].second * Js.transpose();
    for (const auto& r : g.readings) {
      LocalReading l;
      l.step = g.index;
      l.id = r.id;
      l.z = Eigen::Vector2d(r.range, r.yaw);
      l.sensor = sensor;
      l.sensor_cov = sensor_cov;
      Eigen::Matrix<double, 2, 3> Jq;
      Eigen::Matrix2d Jz;
      l.point = readingPoint(r.range, r.yaw, sensor, &Jq, &Jz);
      l.point_cov = Jq * sensor_cov * Jq.transpose() + Jz * R * Jz.transpose();
      out.push_back(l);
    }
  }
  return out;
}

std::vector<SensorView> ReadingWindow::views() const {
  const auto poses = chain();
  std::vector<SensorView> out;
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    const Gathered& g = steps_[k];
    if (!g.scanned) continue;
    out.push_back({g.index, compose(poses[k].first, g.sensor), g.min_range, g.max_range, g.fov});
  }
  return out;
}

std::vector<WindowStep> ReadingWindow::gathered() const {
  const auto poses = chain();
  std::vector<WindowStep> out;
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    const Gathered& g = steps_[k];
    out.push_back({g.index, g.odometry, g.odometry_cov, g.sensor, poses[k].first});
  }
  return out;
}

}  // namespace budget_slam::wakeup
