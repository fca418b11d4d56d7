#include "budget_slam/metrics/LocalizationScore.h"

#include <algorithm>
#include <cmath>

namespace budget_slam::metrics {

LocalizationScorer::LocalizationScorer(double lost_threshold, std::size_t min_landmarks,
                                       double success_xy, double success_yaw)
    : threshold_(lost_threshold),
      k_(min_landmarks),
      success_xy_(success_xy),
      success_yaw_(success_yaw) {}

bool LocalizationScorer::add(double error_m, std::size_t map_landmarks, double nees) {
  StepError e;
  e.error_m = error_m;
  e.map_landmarks = map_landmarks;
  e.nees = nees;
  return add(e);
}

bool LocalizationScorer::add(const StepError& step) {
  const double error_m = step.error_m;
  ++s_.steps;
  landmarks_ += step.map_landmarks;
  s_.covered += step.map_landmarks >= k_;
  nees_.add(step.nees);
  if (std::isnan(error_m)) return false;
  ++s_.compared;
  if (!step.in_mapped_area) return false;
  ++s_.scored;
  if (step.place) {
    auto& [n, ok] = places_[*step.place];
    ++n;
    ok += tracked(error_m, step.yaw_error);
  }
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
  if (s.scored) s.lost_pct = 100.0 * static_cast<double>(s.lost) / static_cast<double>(s.scored);
  if (s.compared)
    s.scored_pct = 100.0 * static_cast<double>(s.scored) / static_cast<double>(s.compared);
  if (!places_.empty()) {
    double sum = 0;
    for (const auto& [key, counts] : places_)
      sum += static_cast<double>(counts.second) / static_cast<double>(counts.first);
    s.places = places_.size();
    s.success_pct = 100.0 * sum / static_cast<double>(places_.size());
  }
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
