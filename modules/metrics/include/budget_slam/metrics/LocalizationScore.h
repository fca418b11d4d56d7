#pragma once
#include <limits>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/metrics/NeesAccumulator.h"

namespace budget_slam::metrics {

/// How well a robot localized in a given map over one traversal (budget-slam localize).
struct LocalizationScore {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t steps = 0;         ///< steps processed
  std::size_t compared = 0;      ///< steps with a true (or reference) pose to compare with
  std::size_t lost = 0;          ///< compared steps with a position error above the threshold
  std::size_t covered = 0;       ///< steps with at least k map landmarks observed
  double rmse_m = kNaN;          ///< position RMSE over the compared steps with a finite estimate
  double max_m = kNaN;           ///< largest position error of those
  double lost_pct = kNaN;        ///< 100 lost / compared
  double coverage_pct = kNaN;    ///< 100 covered / steps
  double mean_landmarks = kNaN;  ///< mean map landmarks observed a step
  double nees_mean = kNaN;       ///< mean pose NEES over the steps where it is defined
  std::size_t nees_samples = 0;
};

/// Accumulates a LocalizationScore step by step (nothing per step is kept).
class LocalizationScorer {
 public:
  /// `lost_threshold` [m]; `min_landmarks` = k.
  LocalizationScorer(double lost_threshold, std::size_t min_landmarks);

  /// One step: its position error [m] (NaN: nothing to compare with; +inf: the estimate is not
  /// finite, a lost step), the map landmarks it observed, its NEES (NaN when undefined). Returns
  /// whether the step counts as lost.
  bool add(double error_m, std::size_t map_landmarks, double nees);
  LocalizationScore score() const;

 private:
  double threshold_;
  std::size_t k_;
  LocalizationScore s_;
  NeesMeanSum nees_;
  double sq_ = 0, max_ = 0;
  std::size_t finite_ = 0, landmarks_ = 0;
};

}  // namespace budget_slam::metrics
