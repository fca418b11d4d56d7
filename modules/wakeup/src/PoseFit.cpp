#include "budget_slam/wakeup/PoseFit.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>

#include "budget_slam/core/RangeBearingModel.h"

namespace budget_slam::wakeup {

std::optional<Pose2> fitRigid(const std::vector<Eigen::Vector2d>& local,
                              const std::vector<Eigen::Vector2d>& map,
                              const std::vector<double>& weights) {
  double W = 0;
  Eigen::Vector2d pc = Eigen::Vector2d::Zero(), mc = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < local.size(); ++i) {
    W += weights[i];
    pc += weights[i] * local[i];
    mc += weights[i] * map[i];
  }
  if (!(W > 0)) return std::nullopt;
  pc /= W;
  mc /= W;
  // Weighted cross terms of the centred points: sum w (p . m) and sum w (p x m).
  double dot = 0, cross = 0, spread = 0;
  for (std::size_t i = 0; i < local.size(); ++i) {
    const Eigen::Vector2d p = local[i] - pc, m = map[i] - mc;
    dot += weights[i] * p.dot(m);
    cross += weights[i] * (p.x() * m.y() - p.y() * m.x());
    spread += weights[i] * p.squaredNorm();
  }
  if (!(spread > 1e-12 * W)) return std::nullopt;
  const double yaw = std::atan2(cross, dot);
  const Eigen::Vector2d t = mc - rot2(yaw) * pc;
  return Pose2(t.x(), t.y(), yaw);
}

Refinement refinePose(const Pose2& start, const std::vector<LocalReading>& readings,
                      const std::vector<LandmarkView>& map, const std::vector<Pairing>& pairs,
                      const ReadingNoise& noise, int max_iterations) {
  const Eigen::Matrix2d R =
      Eigen::Vector2d(noise.std_range * noise.std_range, noise.std_bearing * noise.std_bearing)
          .asDiagonal();
  Refinement out;
  out.pose = start;
  out.chi2.assign(pairs.size(), 0);
  for (int it = 0; it <= max_iterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const LocalReading& r = readings[pairs[k].reading];
      const LandmarkView& l = map[pairs[k].landmark];
      const auto p = predictRangeBearing(out.pose, r.sensor, l.mean);
      Eigen::Vector2d nu = r.z - p.z;
      nu.y() = wrapAngle(nu.y());
      const Eigen::Matrix2d S = R + p.H_sensor * r.sensor_cov * p.H_sensor.transpose() +
                                p.H_landmark * l.cov * p.H_landmark.transpose();
      const Eigen::Matrix2d Si = S.inverse();
      out.chi2[k] = nu.dot(Si * nu);
      H += p.H_robot.transpose() * Si * p.H_robot;
      g += p.H_robot.transpose() * Si * nu;
    }
    out.information = H;
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return out;
    out.cov = ldlt.solve(Eigen::Matrix3d::Identity());
    if (it == max_iterations || out.converged) break;
    // Gauss-Newton step on z - h(X): h(X + dx) ~ h(X) + J dx.
    const Eigen::Vector3d dx = ldlt.solve(g);
    out.pose = Pose2(out.pose.vector() + dx);
    out.pose.phi = wrapAngle(out.pose.phi);
    // One more pass after convergence evaluates chi2 and the covariance at the solution.
    if (dx.head<2>().norm() < 1e-9 && std::abs(dx.z()) < 1e-9) out.converged = true;
  }
  return out;
}

}  // namespace budget_slam::wakeup
