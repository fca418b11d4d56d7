#include "budget_slam/runs/RunObservers.h"

#include <algorithm>
#include <limits>
#include <unordered_set>

#include "budget_slam/runs/ProcessProbes.h"

namespace budget_slam::runs {
namespace {

report::EvictionRow evictionRow(const reducers::Eviction& e) {
  return {e.step,    e.id,     e.reducer, e.score,        e.n_before,
          e.n_after, e.reason, e.shadow,  e.shadow_errors};
}

}  // namespace

void StepProbes::start() {
  t0_ = std::chrono::steady_clock::now();
  cpu0_ = threadCpuSeconds();
}

StepProbes::Sample StepProbes::stop() const {
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(),
          threadCpuSeconds() - cpu0_};
}

void StepProbes::count(const Sample& s) {
  total_s_ += s.wall_s;
  max_s_ = std::max(max_s_, s.wall_s);
}

RunTimings StepProbes::timings(std::size_t steps) const {
  RunTimings t;
  t.steps_s = total_s_;
  t.step_ms_mean = steps ? 1e3 * total_s_ / std::max<std::size_t>(1, steps)
                         : std::numeric_limits<double>::quiet_NaN();
  t.step_ms_max = 1e3 * max_s_;
  t.peak_rss_bytes = peakResidentBytes();
  return t;
}

void EvictionLog::log(const std::vector<reducers::Eviction>& drops, report::RunOutputs& outputs) {
  for (const auto& e : drops) {
    // A refused newcomer never held a place between steps: counted apart from the drops.
    const bool refused = e.reason == "refused";
    ++(refused ? refused_ : evictions_);
    if (!refused && dropped_.size() < kMaxDroppedMarks) dropped_.push_back(e.mean);
    outputs.addEviction(evictionRow(e));
  }
}

RelocCoverageTracking::RelocCoverageTracking(std::size_t min_landmarks, std::size_t max_samples)
    : tracker_(min_landmarks, max_samples) {}

void RelocCoverageTracking::added(const std::vector<LandmarkId>& assoc) {
  for (const LandmarkId id : assoc) tracker_.landmarkAdded(id);
}

void RelocCoverageTracking::removed(const std::vector<reducers::Eviction>& drops) {
  for (const auto& e : drops) tracker_.landmarkRemoved(e.id);
}

std::size_t RelocCoverageTracking::observe(const Step& raw, const Step& filtered,
                                           const std::vector<LandmarkId>& assoc) {
  // A reading with a sensor ID observes that landmark (whether the map holds it or not); one
  // without is known only through the backend's association.
  std::vector<LandmarkId> observed;
  if (raw.scan)
    for (const auto& r : raw.scan->readings)
      if (r.id != kNoLandmarkId) observed.push_back(r.id), saw_ids_ = true;
  if (filtered.scan)
    for (std::size_t r = 0; r < filtered.scan->readings.size(); ++r)
      if (filtered.scan->readings[r].id == kNoLandmarkId) {
        saw_idless_ = true;
        if (r < assoc.size()) observed.push_back(assoc[r]);
      }
  return tracker_.addStep(raw.index, observed);
}

FinalRelocCoverage RelocCoverageTracking::finalCoverage(const Backend& backend) const {
  FinalRelocCoverage c;
  std::unordered_set<LandmarkId> ids;
  for (const auto& l : backend.landmarks()) ids.insert(l.id);
  c.steps = tracker_.steps();
  c.coverage = metrics::coverageOf(
      c.steps, [&](LandmarkId id) { return ids.count(id) > 0; }, tracker_.minLandmarks(),
      tracker_.sampled());
  c.source = saw_idless_ ? (saw_ids_ ? "landmark_ids_and_own_association" : "own_association")
                         : "landmark_ids";
  return c;
}

}  // namespace budget_slam::runs
