#pragma once
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/metrics/NeesAccumulator.h"

namespace budget_slam::metrics {

/// How well a robot localized in a given map over one traversal (budget-slam localize). Errors,
/// lost steps and success are over the scored steps: those with a true (or reference) pose in
/// the area the map was made in (MappedArea; docs/ALGORITHMS.md "Relocalization").
struct LocalizationScore {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t steps = 0;     ///< steps processed
  std::size_t compared = 0;  ///< steps with a true (or reference) pose to compare with
  std::size_t scored = 0;    ///< compared steps in the mapped area
  std::size_t lost = 0;      ///< scored steps with a position error above the threshold
  std::size_t covered = 0;   ///< steps with at least k map landmarks observed
  double rmse_m = kNaN;      ///< position RMSE over the scored steps with a finite estimate
  double max_m = kNaN;       ///< largest position error of those
  double lost_pct = kNaN;    ///< 100 lost / scored
  double scored_pct = kNaN;  ///< 100 scored / compared
  /// Relocalization success per place: for each place (PlaceGrid: cell and heading sector of the
  /// true pose) of the scored steps, the share of its steps tracked (position error at most
  /// success_xy and yaw error at most success_yaw); the mean over places [%].
  double success_pct = kNaN;
  std::size_t places = 0;        ///< places of the scored steps
  double coverage_pct = kNaN;    ///< 100 covered / steps
  double mean_landmarks = kNaN;  ///< mean map landmarks observed a step
  double nees_mean = kNaN;       ///< mean pose NEES over the steps where it is defined
  std::size_t nees_samples = 0;
};

/// One step as the scorer sees it.
struct StepError {
  double error_m = LocalizationScore::kNaN;    ///< NaN: no truth; +inf: the estimate is not finite
  double yaw_error = LocalizationScore::kNaN;  ///< |yaw error| [rad]; NaN: no truth
  std::size_t map_landmarks = 0;               ///< map landmarks observed
  double nees = LocalizationScore::kNaN;       ///< NaN when undefined
  bool in_mapped_area = true;
  std::optional<PlaceKey> place;  ///< the true pose's place (none: no success per place)
};

/// Accumulates a LocalizationScore step by step (per place: two counts).
class LocalizationScorer {
 public:
  /// `lost_threshold` [m]; `min_landmarks` = k; a step is tracked within `success_xy` [m] and
  /// `success_yaw` [rad].
  LocalizationScorer(double lost_threshold, std::size_t min_landmarks, double success_xy = 0.25,
                     double success_yaw = 5 * M_PI / 180);

  /// One step. Returns whether it counts as lost (a scored step above the threshold).
  bool add(const StepError& step);
  /// A step in the mapped area without a place: add({error_m, NaN, map_landmarks, nees}).
  bool add(double error_m, std::size_t map_landmarks, double nees);
  /// True when a step with these errors counts as tracked.
  bool tracked(double error_m, double yaw_error) const {
    return error_m <= success_xy_ && yaw_error <= success_yaw_;
  }
  LocalizationScore score() const;

 private:
  double threshold_;
  std::size_t k_;
  double success_xy_, success_yaw_;
  std::unordered_map<PlaceKey, std::pair<std::size_t, std::size_t>, PlaceKeyHash>
      places_;  ///< steps, tracked steps
  LocalizationScore s_;
  NeesMeanSum nees_;
  double sq_ = 0, max_ = 0;
  std::size_t finite_ = 0, landmarks_ = 0;
};

}  // namespace budget_slam::metrics
