#pragma once
// The observers of the run driver's step loop (StepObserver.h), each measuring or recording one
// thing and filling its own block of the outcome (RunOutcome.h). RunDriver calls them in this
// order: StepProbes (first: it closes the step's timed window), RelocCoverageTracking, MapCounts,
// NeesTracking, EvictionLog, SceneSnapshots.
#include <Eigen/Core>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/engine/FinalRelocCoverage.h"
#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/engine/StepObserver.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/NeesAccumulator.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunOutputs.h"

namespace budget_slam::runs {

/// Wall and CPU time of each step (the calling thread's, so per run when compare runs several
/// in one process) and their totals: summary.json "timings", steps.csv's step_ms, cpu_ms. The
/// timed window runs from stepStarts() to this observer's afterDrops().
class StepProbes : public StepObserver {
 public:
  struct Sample {
    double wall_s = 0, cpu_s = 0;
  };
  void stepStarts() override;
  void afterDrops(const StepEvent&, report::StepRow& row) override;
  void stepDone(const StepEvent&, const report::StepRow&) override;
  /// "timings" (peak resident memory read now).
  void fill(RunOutcome& outcome, std::size_t steps_in_rawlog) const override;

  /// The wall time of the steps counted [s].
  double totalSeconds() const { return total_s_; }
  /// The timings block of the steps counted.
  RunTimings timings() const;

 private:
  std::chrono::steady_clock::time_point t0_;
  double cpu0_ = 0;
  Sample last_;  ///< the step being finished, counted once its row is written
  double total_s_ = 0, max_s_ = 0;
  std::size_t steps_ = 0;
};

/// Relocalization coverage, followed step by step: which landmarks each step observed (by sensor
/// ID, or through the backend's association) against the map as it stands after the step's
/// drops (steps.csv's reloc_landmarks and reloc_coverage_so_far_pct), and the final map's
/// coverage of those steps (summary.json "relocalization").
class RelocCoverageTracking : public StepObserver {
 public:
  /// `max_samples` = 0 keeps every step (metrics::RelocalizationTracker).
  RelocCoverageTracking(std::size_t min_landmarks, std::size_t max_samples);
  /// The landmarks the step's readings went to are in the map now (new ones included).
  void afterUpdate(const StepEvent& e) override;
  /// The map lost the step's drops; the step's observations against the map as it stands now.
  void afterDrops(const StepEvent& e, report::StepRow& row) override;
  void endOfRunDrops(const std::vector<reducers::Eviction>& drops) override;
  /// "relocalization": the coverage settle() fixed (nothing before).
  void fill(RunOutcome& outcome, std::size_t steps_in_rawlog) const override;

  /// The tracked steps against `backend`'s landmarks now.
  FinalRelocCoverage finalCoverage(const Backend& backend) const;
  /// Replaces the final coverage settle() gives (compare on ID-less rawlogs: through the
  /// reference run).
  void replaceFinal(FinalRelocCoverage coverage) { replaced_ = std::move(coverage); }
  /// The final coverage the outcome reports: the replacement, else finalCoverage(backend).
  const FinalRelocCoverage& settle(const Backend& backend);
  const metrics::RelocalizationTracker& tracker() const { return tracker_; }

 private:
  void removed(const std::vector<reducers::Eviction>& drops);

  metrics::RelocalizationTracker tracker_;
  bool saw_ids_ = false, saw_idless_ = false;  ///< readings with / without sensor IDs
  std::optional<FinalRelocCoverage> replaced_, settled_;
};

/// The map's size over the run: the peak and the landmarks added ("counts"), and with the
/// per-step history kept, the landmark count and the online robot pose after each step.
class MapCounts : public StepObserver {
 public:
  /// `keep_history` false keeps no per-step record (memory flat over lifelong runs).
  explicit MapCounts(bool keep_history) : keep_history_(keep_history) {}
  void stepDone(const StepEvent&, const report::StepRow& row) override;
  /// "counts": landmarks_peak, landmarks_added.
  void fill(RunOutcome& outcome, std::size_t steps_in_rawlog) const override;

  /// The online robot pose after each step (empty without history).
  const std::vector<metrics::PoseRecord>& onlinePoses() const { return online_; }
  /// The landmarks in the map after each step (empty without history).
  const std::vector<std::size_t>& landmarkCounts() const { return counts_; }

 private:
  bool keep_history_;
  std::size_t peak_ = 0, added_ = 0;
  std::vector<std::size_t> counts_;
  std::vector<metrics::PoseRecord> online_;
};

/// The pose NEES against the ground truth's path, accumulated online (metrics::NeesAccumulator):
/// summary.json "ground_truth": nees_mean, nees_samples.
class NeesTracking : public StepObserver {
 public:
  explicit NeesTracking(const dataset::GroundTruth& truth) : nees_(truth) {}
  void stepDone(const StepEvent&, const report::StepRow& row) override;
  void fill(RunOutcome& outcome, std::size_t steps_in_rawlog) const override;

 private:
  metrics::NeesAccumulator nees_;
};

/// The budget's drops as they happen: evictions.csv rows, the counts of drops and refusals, and
/// where the dropped landmarks were (map.png's marks, at most kMaxDroppedMarks).
class EvictionLog : public StepObserver {
 public:
  static constexpr std::size_t kMaxDroppedMarks = 20000;  ///< a lifelong run drops millions
  explicit EvictionLog(report::RunOutputs& outputs) : outputs_(outputs) {}
  /// After the step's row: evictions.csv never holds a step steps.csv does not.
  void stepDone(const StepEvent& e, const report::StepRow&) override;
  void endOfRunDrops(const std::vector<reducers::Eviction>& drops) override;
  /// "counts": evictions, refused.
  void fill(RunOutcome& outcome, std::size_t steps_in_rawlog) const override;

  /// Landmarks dropped after holding a place in the map (evictions.csv rows but the refusals).
  std::size_t evictions() const { return evictions_; }
  /// Newcomers refused at admission (evictions.csv rows with reason refused).
  std::size_t refused() const { return refused_; }
  const std::vector<Eigen::Vector2d>& droppedMarks() const { return dropped_; }

 private:
  void log(const std::vector<reducers::Eviction>& drops);

  report::RunOutputs& outputs_;
  std::size_t evictions_ = 0, refused_ = 0;
  std::vector<Eigen::Vector2d> dropped_;
};

/// kf-slam's periodic scenes: kf_state_<step>.3Dscene every `every_steps` steps (SAVE_3D_SCENES,
/// SAVE_LOG_FREQUENCY), the map as `content` draws it after the step's drops.
class SceneSnapshots : public StepObserver {
 public:
  SceneSnapshots(std::size_t every_steps, const report::RunOutputs& outputs,
                 std::function<report::MapContent()> content)
      : every_steps_(every_steps), outputs_(outputs), content_(std::move(content)) {}
  void stepDone(const StepEvent& e, const report::StepRow& row) override;

 private:
  std::size_t every_steps_;
  const report::RunOutputs& outputs_;
  std::function<report::MapContent()> content_;
};

}  // namespace budget_slam::runs
