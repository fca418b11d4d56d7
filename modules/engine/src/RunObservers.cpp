#include "budget_slam/engine/RunObservers.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <unordered_set>

#include "budget_slam/engine/ProcessProbes.h"

namespace budget_slam::runs {
namespace {

report::EvictionRow evictionRow(const reducers::Eviction& e) {
  return {e.step,    e.id,     e.reducer, e.score,        e.n_before,
          e.n_after, e.reason, e.shadow,  e.shadow_errors};
}

}  // namespace

void StepProbes::stepStarts() {
  t0_ = std::chrono::steady_clock::now();
  cpu0_ = threadCpuSeconds();
}

void StepProbes::afterDrops(const StepEvent&, report::StepRow& row) {
  last_ = {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(),
           threadCpuSeconds() - cpu0_};
  row.step_ms = 1e3 * last_.wall_s;
  row.cpu_ms = 1e3 * last_.cpu_s;
}

void StepProbes::stepDone(const StepEvent&, const report::StepRow&) {
  total_s_ += last_.wall_s;
  max_s_ = std::max(max_s_, last_.wall_s);
  ++steps_;
}

RunTimings StepProbes::timings() const {
  RunTimings t;
  t.steps_s = total_s_;
  t.step_ms_mean = steps_ ? 1e3 * total_s_ / static_cast<double>(steps_)
                          : std::numeric_limits<double>::quiet_NaN();
  t.step_ms_max = 1e3 * max_s_;
  t.peak_rss_bytes = peakResidentBytes();
  return t;
}

void StepProbes::fill(RunOutcome& outcome, std::size_t) const { outcome.run->timings = timings(); }

RelocCoverageTracking::RelocCoverageTracking(std::size_t min_landmarks, std::size_t max_samples)
    : tracker_(min_landmarks, max_samples) {}

void RelocCoverageTracking::afterUpdate(const StepEvent& e) {
  for (const LandmarkId id : e.association) tracker_.landmarkAdded(id);
}

void RelocCoverageTracking::removed(const std::vector<reducers::Eviction>& drops) {
  for (const auto& d : drops) tracker_.landmarkRemoved(d.id);
}

void RelocCoverageTracking::afterDrops(const StepEvent& e, report::StepRow& row) {
  // The coverage over time counts the map as it stands after this step's drops.
  removed(e.drops);
  // A reading with a sensor ID observes that landmark (whether the map holds it or not); one
  // without is known only through the backend's association.
  std::vector<LandmarkId> observed;
  if (e.raw.scan)
    for (const auto& r : e.raw.scan->readings)
      if (r.id != kNoLandmarkId) observed.push_back(r.id), saw_ids_ = true;
  if (e.filtered.scan)
    for (std::size_t r = 0; r < e.filtered.scan->readings.size(); ++r)
      if (e.filtered.scan->readings[r].id == kNoLandmarkId) {
        saw_idless_ = true;
        if (r < e.association.size()) observed.push_back(e.association[r]);
      }
  row.reloc_landmarks = tracker_.addStep(e.raw.index, observed);
  row.reloc_coverage_so_far_pct = tracker_.coverageSoFarPct();
}

void RelocCoverageTracking::endOfRunDrops(const std::vector<reducers::Eviction>& drops) {
  removed(drops);
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

const FinalRelocCoverage& RelocCoverageTracking::settle(const Backend& backend) {
  settled_ = replaced_ ? *replaced_ : finalCoverage(backend);
  return *settled_;
}

void RelocCoverageTracking::fill(RunOutcome& outcome, std::size_t) const {
  if (settled_)
    outcome.run->relocalization = {settled_->coverage, settled_->source, settled_->details};
}

void MapCounts::stepDone(const StepEvent&, const report::StepRow& row) {
  added_ += row.added;
  peak_ = std::max(peak_, row.landmarks);
  if (keep_history_) counts_.push_back(row.landmarks);
  if (keep_history_) online_.push_back({row.step, row.pose});
}

void MapCounts::fill(RunOutcome& outcome, std::size_t) const {
  outcome.run->counts.landmarks_peak = peak_;
  outcome.run->counts.landmarks_added = added_;
}

void NeesTracking::stepDone(const StepEvent&, const report::StepRow& row) {
  nees_.add(row.step, row.pose);
}

void NeesTracking::fill(RunOutcome& outcome, std::size_t steps_in_rawlog) const {
  if (outcome.ground_truth) outcome.ground_truth->nees = nees_.result(steps_in_rawlog);
}

void EvictionLog::log(const std::vector<reducers::Eviction>& drops) {
  for (const auto& e : drops) {
    // A refused newcomer never held a place between steps: counted apart from the drops.
    const bool refused = e.reason == "refused";
    ++(refused ? refused_ : evictions_);
    if (!refused && dropped_.size() < kMaxDroppedMarks) dropped_.push_back(e.mean);
    outputs_.addEviction(evictionRow(e));
  }
}

void EvictionLog::stepDone(const StepEvent& e, const report::StepRow&) { log(e.drops); }

void EvictionLog::endOfRunDrops(const std::vector<reducers::Eviction>& drops) { log(drops); }

void EvictionLog::fill(RunOutcome& outcome, std::size_t) const {
  outcome.run->counts.evictions = evictions_;
  outcome.run->counts.refused = refused_;
}

void SceneSnapshots::stepDone(const StepEvent& e, const report::StepRow& row) {
  if (row.step % every_steps_ != 0) return;
  char name[48];
  std::snprintf(name, sizeof name, "kf_state_%05llu.3Dscene",
                static_cast<unsigned long long>(row.step));
  outputs_.writeScene(name, content_(), e.backend.robotPose().mean);
}

}  // namespace budget_slam::runs
