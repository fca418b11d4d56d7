#pragma once
// Hand-made worlds for the wake-up tests: landmarks, a robot path, and the steps a range-bearing
// sensor on it would record.
#include <cmath>
#include <random>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Step.h"

namespace budget_slam::wakeup::test {

struct WorldLandmark {
  LandmarkId id;
  Eigen::Vector2d p;
};

/// A saved map: the world's landmarks with a marginal of `std` [m] each.
inline std::vector<LandmarkView> mapOf(const std::vector<WorldLandmark>& world, double std = 0.05) {
  std::vector<LandmarkView> out;
  for (const auto& w : world) {
    LandmarkView v;
    v.id = w.id;
    v.mean = w.p;
    v.cov = Eigen::Matrix2d::Identity() * std * std;
    out.push_back(v);
  }
  return out;
}

struct SensorSetup {
  Pose2 on_robot;
  double max_range = 15, fov = 2 * M_PI;
  double std_range = 0.0, std_bearing = 0.0;  ///< noise added to the readings
  bool with_ids = true;
};

/// The steps of a robot driving `path` (poses in the world): odometry from pose to pose (its
/// covariance `odo_std`, noise added with it), and the readings of every landmark in range and
/// view, in landmark order.
inline std::vector<Step> stepsAlong(const std::vector<Pose2>& path,
                                    const std::vector<WorldLandmark>& world,
                                    const SensorSetup& sensor, std::mt19937& rng,
                                    double odo_std = 0.0, StepIndex first_index = 0) {
  std::normal_distribution<double> g;
  std::vector<Step> out;
  for (std::size_t k = 0; k < path.size(); ++k) {
    Step s;
    s.index = first_index + k;
    s.t = static_cast<double>(s.index);
    if (k > 0) {
      OdometryIncrement o;
      Pose2 u = between(path[k - 1], path[k]);
      u = Pose2(u.vector() + Eigen::Vector3d(g(rng), g(rng), g(rng) * 0.1) * odo_std);
      o.mean = u;
      const double v = std::max(odo_std * odo_std, 1e-8);
      o.cov = Eigen::Vector3d(v, v, v * 0.01).asDiagonal();
      s.odometry = o;
    }
    RangeBearingScan scan;
    scan.sensor_pose_on_robot =
        mrpt::math::TPose3D(sensor.on_robot.x, sensor.on_robot.y, 0, sensor.on_robot.phi, 0, 0);
    scan.max_range = sensor.max_range;
    scan.fov_yaw = sensor.fov;
    const Pose2 sp = compose(path[k], sensor.on_robot);
    for (const auto& w : world) {
      const Eigen::Vector2d d = sp.transformTo(w.p);
      const double r = d.norm(), b = std::atan2(d.y(), d.x());
      if (r > sensor.max_range || std::abs(b) > sensor.fov / 2 || r <= 0) continue;
      RangeBearingReading rd;
      rd.id = sensor.with_ids ? w.id : kNoLandmarkId;
      rd.range = r + sensor.std_range * g(rng);
      rd.yaw = wrapAngle(b + sensor.std_bearing * g(rng));
      scan.readings.push_back(rd);
    }
    s.scan = scan;
    out.push_back(s);
  }
  return out;
}

/// A straight drive from `start`, `n` poses `step` metres apart.
inline std::vector<Pose2> straightPath(const Pose2& start, std::size_t n, double step) {
  std::vector<Pose2> p;
  for (std::size_t k = 0; k < n; ++k) p.push_back(compose(start, Pose2(step * k, 0, 0)));
  return p;
}

}  // namespace budget_slam::wakeup::test
