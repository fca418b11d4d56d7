#include "budget_slam/metrics/LocalizationScore.h"

#include <algorithm>
#include <cmath>

namespace budget_slam::metrics {

LocalizationScorer::LocalizationScorer(double lost_threshold, std::size_t min_landmarks)
    : threshold_(lost_threshold), k_(min_landmarks) {}

bool LocalizationScorer::add(double error_m, std::size_t map_landmarks, double nees) {
  ++s_.steps;
  landmarks_ += map_landmarks;
  s_.covered += map_landmarks >= k_;
  nees_.add(nees);
  if (std::isnan(error_m)) return false;
  ++s_.compared;
  const bool lost = !(error_m <= threshold_);
  s_.lost += lost;
  if (std::isfinite(error_m)) {
    sq_ += error_m * error_m;
    max_ = std::max(max_, error_m);
    ++finite_;
  }
  return lost;
}

LocalizationScore LocalizationScorer::score() const {
  LocalizationScore s = s_;
  if (finite_) s.rmse_m = std::sqrt(sq_ / static_cast<double>(finite_)), s.max_m = max_;
  if (s.compared)
    s.lost_pct = 100.0 * static_cast<double>(s.lost) / static_cast<double>(s.compared);
  if (s.steps) {
    s.coverage_pct = 100.0 * static_cast<double>(s.covered) / static_cast<double>(s.steps);
    s.mean_landmarks = static_cast<double>(landmarks_) / static_cast<double>(s.steps);
  }
  const NeesMean nees = nees_.result();
  s.nees_samples = nees.samples;
  s.nees_mean = nees.mean;
  return s;
}

}  // namespace budget_slam::metrics
