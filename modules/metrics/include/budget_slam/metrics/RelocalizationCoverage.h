#pragma once
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "budget_slam/core/Estimates.h"

namespace budget_slam::metrics {

/// Relocalization coverage of a map over the steps of a rawlog (Hochdorfer & Schlegel's argument:
/// a kept map must let the robot relocalize wherever it works): at every step, how many landmarks
/// of the map the robot observed there, and the share of steps with at least k of them.
struct RelocalizationCoverage {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t min_landmarks = 2;  ///< k ([Metrics] reloc_min_landmarks)
  std::size_t steps = 0;          ///< steps counted (every step, or the sample)
  std::size_t steps_covered = 0;  ///< of those, steps with >= k map landmarks observed
  double coverage_pct = kNaN;     ///< 100 steps_covered / steps
  double mean_landmarks = kNaN;   ///< mean number of map landmarks observed a step
  bool sampled = false;           ///< true when only a sample of the steps was kept
};

/// The landmarks observed at one step (distinct ids) and how many of them the map holds.
struct ObservedAtStep {
  StepIndex step = 0;
  std::vector<LandmarkId> ids;
  std::uint32_t in_map = 0;
};

/// Coverage of `steps` against the map given by `in_map`; fills each step's `in_map` count.
RelocalizationCoverage coverageOf(std::vector<ObservedAtStep>& steps,
                                  const std::function<bool(LandmarkId)>& in_map,
                                  std::size_t min_landmarks, bool sampled = false);

/// Follows a run step by step: which landmarks each step observed, which the map holds now, and
/// so the coverage of the map held at step t over the steps visited up to t ("so far"), updated
/// incrementally: a landmark entering the map adds one to every kept step that observed it, a
/// dropped one subtracts one. Cost: O(readings) for the steps, O(sightings of a landmark) for each
/// drop or readmission.
///
/// `max_samples` = 0 keeps every step (exact). Otherwise memory is bounded: at most
/// `max_samples` steps are kept, every stride-th one; when full, every other kept step goes and
/// the stride doubles, so the kept steps stay evenly spread over the run.
class RelocalizationTracker {
 public:
  explicit RelocalizationTracker(std::size_t min_landmarks = 2, std::size_t max_samples = 0);

  /// The map gained (or regained) `id`. No-op if it holds it already.
  void landmarkAdded(LandmarkId id);
  /// The map lost `id`. No-op if it did not hold it.
  void landmarkRemoved(LandmarkId id);
  bool inMap(LandmarkId id) const { return in_map_.count(id) != 0; }

  /// The next step and the landmarks it observed (duplicates and kNoLandmarkId ignored), after
  /// the map changes of that step. Returns how many of them the map holds.
  std::size_t addStep(StepIndex step, const std::vector<LandmarkId>& observed);

  /// The coverage of the current map over the kept steps so far [%]; NaN before the first step.
  double coverageSoFarPct() const;
  /// The same with the mean count, as the final numbers once the run is over.
  RelocalizationCoverage coverage() const;
  /// The kept steps with their counts against the current map.
  const std::vector<ObservedAtStep>& steps() const { return samples_; }
  std::size_t minLandmarks() const { return k_; }
  bool sampled() const { return stride_ > 1; }

 private:
  void adjust(LandmarkId id, int delta);
  void thin();

  std::size_t k_, max_samples_;
  std::vector<ObservedAtStep> samples_;
  std::vector<std::size_t> ordinal_;  ///< for each kept step, its position among all steps
  std::unordered_map<LandmarkId, std::vector<std::uint32_t>> slots_;  ///< id -> kept steps
  std::unordered_set<LandmarkId> in_map_;
  std::size_t covered_ = 0, sum_ = 0, seen_ = 0, stride_ = 1;
};

/// One-to-one pairing of the landmarks of `map` with those of `reference` (both estimates of the
/// same rawlog, without sensor IDs): pairs are taken greedily by increasing squared Mahalanobis
/// distance d^2 = (a - b)' (C_a + C_b)^-1 (a - b), each landmark at most once, up to `gate_chi2`.
/// Returns map id -> reference id.
std::map<LandmarkId, LandmarkId> matchLandmarks(const std::vector<LandmarkView>& map,
                                                const std::vector<LandmarkView>& reference,
                                                double gate_chi2);

}  // namespace budget_slam::metrics
