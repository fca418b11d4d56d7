#include "budget_slam/metrics/NeesAccumulator.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "budget_slam/metrics/GroundTruthErrors.h"

namespace budget_slam::metrics {

double poseNees(const PoseEstimate& estimate, const Pose2& truth) {
  const Eigen::Vector3d e(estimate.mean.x - truth.x, estimate.mean.y - truth.y,
                          mrpt::math::wrapToPi(estimate.mean.phi - truth.phi));
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(estimate.cov);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all())
    return std::numeric_limits<double>::quiet_NaN();
  return e.dot(ldlt.solve(e));
}

NeesAccumulator::NeesAccumulator(const dataset::GroundTruth& truth) {
  if (!truth.path.empty()) path_ = toEstimateFrame(truth).path;
}

void NeesAccumulator::add(StepIndex step, const PoseEstimate& pose) {
  for (const std::size_t offset : {0, 1}) {
    const std::size_t row = step + offset;
    if (row >= path_.size()) continue;
    // Not counted when undefined, e.g. the zero covariance before the first motion.
    sums_[offset].add(poseNees(pose, path_[row]));
  }
}

NeesMean NeesAccumulator::result(std::size_t steps_in_rawlog) const {
  const std::size_t offset = path_.empty() ? 1 : groundTruthRow(0, path_.size(), steps_in_rawlog);
  return sums_[offset].result();
}

}  // namespace budget_slam::metrics
