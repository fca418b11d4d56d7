#include "budget_slam/metrics/GroundTruthErrors.h"

#include <mrpt/poses/CPoint2D.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <string>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/MrptPose.h"

namespace budget_slam::metrics {

void requireFinite(const std::vector<TrajectoryPoint>& trajectory,
                   const std::vector<LandmarkView>& landmarks, const std::string& what) {
  for (const auto& p : trajectory)
    if (!std::isfinite(p.pose.x) || !std::isfinite(p.pose.y) || !std::isfinite(p.pose.phi))
      throw Error(what + ": the pose of step " + std::to_string(p.step) + " is not finite");
  for (const auto& l : landmarks)
    if (!l.mean.allFinite())
      throw Error(what + ": landmark " + std::to_string(l.id) + " is not finite");
}

std::size_t groundTruthRow(StepIndex step, std::size_t path_rows, std::size_t steps) {
  return path_rows == steps ? step : step + 1;
}

dataset::GroundTruth toEstimateFrame(const dataset::GroundTruth& truth) {
  dataset::GroundTruth out = truth;
  if (truth.path.empty()) return out;
  const mrpt::poses::CPose2D inv = -mrpt::poses::CPose2D(toTPose2D(truth.path.front()));
  for (auto& p : out.path) p = toPose2((inv + mrpt::poses::CPose2D(toTPose2D(p))).asTPose());
  for (auto& [id, l] : out.landmarks) {
    const auto q = inv + mrpt::poses::CPoint2D(l.x(), l.y());
    l = Eigen::Vector2d(q.x(), q.y());
  }
  return out;
}

RigidTransform2 alignPoints(const std::vector<Eigen::Vector2d>& a,
                            const std::vector<Eigen::Vector2d>& b) {
  RigidTransform2 T;
  if (a.size() < 2 || a.size() != b.size()) return T;
  Eigen::Vector2d ma = Eigen::Vector2d::Zero(), mb = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= a.size(), mb /= b.size();
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) H += (a[i] - ma) * (b[i] - mb).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d D = Eigen::Matrix2d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) D(1, 1) = -1;  // no mirror
  T.R = svd.matrixV() * D * svd.matrixU().transpose();
  T.t = mb - T.R * ma;
  return T;
}

GroundTruthErrors groundTruthErrors(const std::vector<TrajectoryPoint>& trajectory,
                                    const std::vector<LandmarkView>& landmarks,
                                    const dataset::GroundTruth& raw_truth, std::size_t steps) {
  requireFinite(trajectory, landmarks, "errors against ground truth");
  GroundTruthErrors out;
  // Frame of the estimate: the ground-truth start pose is its origin.
  const dataset::GroundTruth truth = toEstimateFrame(raw_truth);
  const auto& path = truth.path;

  RigidTransform2 align;
  bool aligned = false;
  if (!path.empty()) {
    double sum = 0, mx = 0;
    std::vector<Eigen::Vector2d> est, ref;
    std::vector<Pose2> est_poses, ref_poses;
    for (const auto& p : trajectory) {
      const std::size_t row = groundTruthRow(p.step, path.size(), steps);
      if (row >= path.size()) continue;
      const auto& gt = path[row];
      const double d = std::hypot(p.pose.x - gt.x, p.pose.y - gt.y);
      sum += d * d;
      mx = std::max(mx, d);
      ++out.poses;
      est.emplace_back(p.pose.x, p.pose.y);
      ref.emplace_back(gt.x, gt.y);
      est_poses.push_back(p.pose);
      ref_poses.push_back(gt);
    }
    out.rpe = relativePoseError(est_poses, ref_poses);
    if (out.poses) {
      out.trajectory_rmse = std::sqrt(sum / out.poses);
      out.trajectory_max = mx;
    }
    if (est.size() >= 2) {
      align = alignPoints(est, ref);
      aligned = true;
      double asum = 0;
      for (std::size_t i = 0; i < est.size(); ++i)
        asum += (align.apply(est[i]) - ref[i]).squaredNorm();
      out.trajectory_rmse_aligned = std::sqrt(asum / est.size());
      out.alignment_rotation_deg = std::atan2(align.R(1, 0), align.R(0, 0)) * 180.0 / M_PI;
    }
  }

  if (!truth.landmarks.empty()) {
    double sum = 0, asum = 0;
    for (const auto& l : landmarks) {
      const auto it = truth.landmarks.find(l.id);
      if (it == truth.landmarks.end()) continue;
      sum += (l.mean - it->second).squaredNorm();
      if (aligned) asum += (align.apply(l.mean) - it->second).squaredNorm();
      ++out.landmarks;
    }
    if (out.landmarks) out.landmark_rmse = std::sqrt(sum / out.landmarks);
    if (out.landmarks && aligned) out.landmark_rmse_aligned = std::sqrt(asum / out.landmarks);
  }
  return out;
}

}  // namespace budget_slam::metrics
