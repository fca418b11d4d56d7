#include "budget_slam/metrics/RelativePoseError.h"

#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>

#include "budget_slam/core/MrptPose.h"

namespace budget_slam::metrics {

RelativePoseError relativePoseError(const std::vector<Pose2>& estimate,
                                    const std::vector<Pose2>& truth, double delta) {
  RelativePoseError out;
  const std::size_t n = std::min(estimate.size(), truth.size());
  double sum = 0, mx = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    // The path from i, summed pose to pose from i (not a difference of running sums, whose
    // round-off would move a stretch that ends exactly at delta).
    double path = 0;
    std::size_t j = i + 1;
    for (; j < n; ++j) {
      path += std::hypot(truth[j].x - truth[j - 1].x, truth[j].y - truth[j - 1].y);
      if (path >= delta) break;
    }
    if (j == n) break;  // the path from i never reaches delta, nor from any later pose
    using mrpt::poses::CPose2D;
    const CPose2D moved_truth =
        CPose2D(toTPose2D(truth[j])) - CPose2D(toTPose2D(truth[i]));  // G_i⁻¹ G_j
    const CPose2D moved_estimate =
        CPose2D(toTPose2D(estimate[j])) - CPose2D(toTPose2D(estimate[i]));  // E_i⁻¹ E_j
    const CPose2D e = moved_estimate - moved_truth;  // (G_i⁻¹ G_j)⁻¹ (E_i⁻¹ E_j)
    const double d = std::hypot(e.x(), e.y());
    sum += d * d;
    mx = std::max(mx, d);
    ++out.pairs;
  }
  if (out.pairs) {
    out.rmse = std::sqrt(sum / out.pairs);
    out.max = mx;
  }
  return out;
}

}  // namespace budget_slam::metrics
