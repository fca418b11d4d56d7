#include "budget_slam/metrics/RelocalizationCoverage.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace budget_slam::metrics {
namespace {

/// Distinct real ids of `observed`, sorted.
std::vector<LandmarkId> distinctIds(const std::vector<LandmarkId>& observed) {
  std::vector<LandmarkId> ids;
  ids.reserve(observed.size());
  for (const LandmarkId id : observed)
    if (id != kNoLandmarkId) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace

RelocalizationCoverage coverageOf(std::vector<ObservedAtStep>& steps,
                                  const std::function<bool(LandmarkId)>& in_map,
                                  std::size_t min_landmarks, bool sampled) {
  RelocalizationCoverage c;
  c.min_landmarks = min_landmarks;
  c.sampled = sampled;
  std::size_t sum = 0;
  for (auto& s : steps) {
    s.in_map = static_cast<std::uint32_t>(std::count_if(s.ids.begin(), s.ids.end(), in_map));
    sum += s.in_map;
    c.steps_covered += s.in_map >= min_landmarks;
  }
  c.steps = steps.size();
  if (c.steps) {
    c.coverage_pct = 100.0 * static_cast<double>(c.steps_covered) / static_cast<double>(c.steps);
    c.mean_landmarks = static_cast<double>(sum) / static_cast<double>(c.steps);
  }
  return c;
}

RelocalizationTracker::RelocalizationTracker(std::size_t min_landmarks, std::size_t max_samples)
    : k_(min_landmarks), max_samples_(max_samples) {}

void RelocalizationTracker::adjust(LandmarkId id, int delta) {
  const auto it = slots_.find(id);
  if (it == slots_.end()) return;
  for (const std::uint32_t slot : it->second) {
    auto& s = samples_[slot];
    const bool was = s.in_map >= k_;
    s.in_map = static_cast<std::uint32_t>(static_cast<long long>(s.in_map) + delta);
    sum_ = static_cast<std::size_t>(static_cast<long long>(sum_) + delta);
    const bool is = s.in_map >= k_;
    if (was != is) covered_ = is ? covered_ + 1 : covered_ - 1;
  }
}

void RelocalizationTracker::landmarkAdded(LandmarkId id) {
  if (id == kNoLandmarkId || !in_map_.insert(id).second) return;
  adjust(id, +1);
}

void RelocalizationTracker::landmarkRemoved(LandmarkId id) {
  if (in_map_.erase(id) == 0) return;
  adjust(id, -1);
}

std::size_t RelocalizationTracker::addStep(StepIndex step, const std::vector<LandmarkId>& observed) {
  const std::size_t position = seen_++;
  std::vector<LandmarkId> ids = distinctIds(observed);
  const auto in_map = static_cast<std::uint32_t>(
      std::count_if(ids.begin(), ids.end(), [&](LandmarkId id) { return inMap(id); }));
  if (position % stride_ != 0) return in_map;

  const auto slot = static_cast<std::uint32_t>(samples_.size());
  for (const LandmarkId id : ids) slots_[id].push_back(slot);
  samples_.push_back({step, std::move(ids), in_map});
  ordinal_.push_back(position);
  sum_ += in_map;
  covered_ += in_map >= k_;
  if (max_samples_ > 0 && samples_.size() > max_samples_) thin();
  return in_map;
}

void RelocalizationTracker::thin() {
  // Keep the steps whose position is a multiple of the doubled stride (about half of them).
  stride_ *= 2;
  std::vector<ObservedAtStep> kept;
  std::vector<std::size_t> kept_ordinal;
  for (std::size_t i = 0; i < samples_.size(); ++i)
    if (ordinal_[i] % stride_ == 0) {
      kept.push_back(std::move(samples_[i]));
      kept_ordinal.push_back(ordinal_[i]);
    }
  samples_ = std::move(kept);
  ordinal_ = std::move(kept_ordinal);
  slots_.clear();
  covered_ = sum_ = 0;
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    for (const LandmarkId id : samples_[i].ids) slots_[id].push_back(static_cast<std::uint32_t>(i));
    sum_ += samples_[i].in_map;
    covered_ += samples_[i].in_map >= k_;
  }
}

double RelocalizationTracker::coverageSoFarPct() const {
  if (samples_.empty()) return std::numeric_limits<double>::quiet_NaN();
  return 100.0 * static_cast<double>(covered_) / static_cast<double>(samples_.size());
}

RelocalizationCoverage RelocalizationTracker::coverage() const {
  RelocalizationCoverage c;
  c.min_landmarks = k_;
  c.sampled = sampled();
  c.steps = samples_.size();
  c.steps_covered = covered_;
  if (c.steps) {
    c.coverage_pct = coverageSoFarPct();
    c.mean_landmarks = static_cast<double>(sum_) / static_cast<double>(c.steps);
  }
  return c;
}

std::map<LandmarkId, LandmarkId> matchLandmarks(const std::vector<LandmarkView>& map,
                                                const std::vector<LandmarkView>& reference,
                                                double gate_chi2) {
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < map.size(); ++i)
    for (std::size_t j = 0; j < reference.size(); ++j) {
      const Eigen::Vector2d d = map[i].mean - reference[j].mean;
      const Eigen::LLT<Eigen::Matrix2d> llt(map[i].cov + reference[j].cov);
      // Two exactly known positions (zero covariances) pair only when they coincide.
      const double d2 = llt.info() == Eigen::Success ? d.dot(llt.solve(d))
                        : d.isZero()                 ? 0.0
                                                     : std::numeric_limits<double>::infinity();
      if (d2 <= gate_chi2) pairs.emplace_back(d2, i, j);
    }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> map_used(map.size()), ref_used(reference.size());
  std::map<LandmarkId, LandmarkId> out;
  for (const auto& [d2, i, j] : pairs) {
    if (map_used[i] || ref_used[j]) continue;
    map_used[i] = ref_used[j] = true;
    out[map[i].id] = reference[j].id;
  }
  return out;
}

}  // namespace budget_slam::metrics
