#include "budget_slam/metrics/GroundTruthErrors.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPoint2D.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Cholesky>
#include <cmath>

namespace budget_slam::metrics {

std::size_t groundTruthRow(StepIndex step, std::size_t path_rows, std::size_t steps) {
  return path_rows == steps + 1 ? step + 1 : step;
}

double poseNees(const PoseEstimate& estimate, const mrpt::math::TPose2D& truth) {
  const Eigen::Vector3d e(estimate.mean.x - truth.x, estimate.mean.y - truth.y,
                          mrpt::math::wrapToPi(estimate.mean.phi - truth.phi));
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(estimate.cov);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all())
    return std::numeric_limits<double>::quiet_NaN();
  return e.dot(ldlt.solve(e));
}

dataset::GroundTruth toEstimateFrame(const dataset::GroundTruth& truth) {
  dataset::GroundTruth out = truth;
  if (truth.path.empty()) return out;
  const mrpt::poses::CPose2D inv = -mrpt::poses::CPose2D(truth.path.front());
  for (auto& p : out.path) p = (inv + mrpt::poses::CPose2D(p)).asTPose();
  for (auto& [id, l] : out.landmarks) {
    const auto q = inv + mrpt::poses::CPoint2D(l.x(), l.y());
    l = Eigen::Vector2d(q.x(), q.y());
  }
  return out;
}

GroundTruthErrors groundTruthErrors(const std::vector<TrajectoryPoint>& trajectory,
                                    const std::vector<PoseRecord>& online,
                                    const std::vector<LandmarkView>& landmarks,
                                    const dataset::GroundTruth& raw_truth, std::size_t steps) {
  GroundTruthErrors out;
  // Frame of the estimate: the ground-truth start pose is its origin.
  const dataset::GroundTruth truth = toEstimateFrame(raw_truth);
  const auto& path = truth.path;

  if (!path.empty()) {
    double sum = 0, mx = 0;
    for (const auto& p : trajectory) {
      const std::size_t row = groundTruthRow(p.step, path.size(), steps);
      if (row >= path.size()) continue;
      const auto& gt = path[row];
      const double d = std::hypot(p.pose.x - gt.x, p.pose.y - gt.y);
      sum += d * d;
      mx = std::max(mx, d);
      ++out.poses;
    }
    if (out.poses) {
      out.trajectory_rmse = std::sqrt(sum / out.poses);
      out.trajectory_max = mx;
    }
    double nees = 0;
    for (const auto& r : online) {
      const std::size_t row = groundTruthRow(r.step, path.size(), steps);
      if (row >= path.size()) continue;
      const double n = poseNees(r.estimate, path[row]);
      if (!std::isfinite(n)) continue;  // e.g. the zero covariance before the first motion
      nees += n;
      ++out.nees_samples;
    }
    if (out.nees_samples) out.nees_mean = nees / out.nees_samples;
  }

  if (!truth.landmarks.empty()) {
    double sum = 0;
    for (const auto& l : landmarks) {
      const auto it = truth.landmarks.find(l.id);
      if (it == truth.landmarks.end()) continue;
      sum += (l.mean - it->second).squaredNorm();
      ++out.landmarks;
    }
    if (out.landmarks) out.landmark_rmse = std::sqrt(sum / out.landmarks);
  }
  return out;
}

}  // namespace budget_slam::metrics
