#pragma once
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/dataset/GroundTruth.h"

namespace budget_slam::metrics {

/// Normalized estimation error squared of a robot pose: with e the (x, y, yaw) error of
/// `estimate` w.r.t. `truth` (yaw wrapped to (-pi, pi]), e' P^-1 e (unitless; 3 on average for a
/// consistent filter). NaN when P is not positive definite (the zero covariance before the first
/// motion).
double poseNees(const PoseEstimate& estimate, const Pose2& truth);

/// The mean pose NEES of a run (summary.json "ground_truth": nees_mean, nees_samples).
struct NeesMean {
  double mean = std::numeric_limits<double>::quiet_NaN();  ///< NaN without a sample
  std::size_t samples = 0;                                 ///< steps with a defined NEES
};

/// The mean of the NEES values added, the undefined ones (NaN, inf) left out: the one place a
/// run's (NeesAccumulator) and a traversal's (LocalizationScorer) NEES mean is summed.
class NeesMeanSum {
 public:
  /// Adds `nees` when finite; returns whether it counted.
  bool add(double nees) {
    if (!std::isfinite(nees)) return false;
    sum_ += nees;
    ++samples_;
    return true;
  }
  NeesMean result() const {
    NeesMean out;
    out.samples = samples_;
    if (samples_) out.mean = sum_ / static_cast<double>(samples_);
    return out;
  }

 private:
  double sum_ = 0;
  std::size_t samples_ = 0;
};

/// The run's pose NEES against ground truth, accumulated online one step at a time (no per-step
/// history: lifelong runs stay flat in memory). Which ground-truth row is step k's
/// (groundTruthRow) depends on the rawlog's step count, known only at the end, so both
/// conventions (row k and row k+1) are summed until result() picks one.
class NeesAccumulator {
 public:
  /// `truth` as read from its files; its path is brought into the estimate's frame
  /// (toEstimateFrame). Without a path, result() has no sample.
  explicit NeesAccumulator(const dataset::GroundTruth& truth);

  /// Adds the NEES of the online pose after step `step` (skipped when not defined or when the
  /// path has no row for the step).
  void add(StepIndex step, const PoseEstimate& pose);

  /// The mean over the steps added, with rows mapped for a rawlog of `steps_in_rawlog` steps.
  NeesMean result(std::size_t steps_in_rawlog) const;

 private:
  std::vector<Pose2> path_;  ///< ground-truth path in the estimate's frame
  NeesMeanSum sums_[2];      ///< by row offset (step k is row k + offset)
};

}  // namespace budget_slam::metrics
