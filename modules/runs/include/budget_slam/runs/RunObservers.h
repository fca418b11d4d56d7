#pragma once
// What the run driver's step loop (backend + budget) hands each step to: the observers that
// measure the run, each filling its own block of the outcome (RunOutcome.h). The NEES observer
// is metrics::NeesAccumulator.
#include <Eigen/Core>
#include <chrono>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/report/RunOutputs.h"
#include "budget_slam/runs/FinalRelocCoverage.h"
#include "budget_slam/runs/RunOutcome.h"

namespace budget_slam::runs {

/// Wall and CPU time of each step (the calling thread's, so per run when compare runs several
/// in one process) and their totals: summary.json "timings", steps.csv's step_ms, cpu_ms.
class StepProbes {
 public:
  struct Sample {
    double wall_s = 0, cpu_s = 0;
  };
  /// Before the step's work.
  void start();
  /// After it: the step's times (not counted yet).
  Sample stop() const;
  /// The step counts (its steps.csv row is written).
  void count(const Sample& s);
  double totalSeconds() const { return total_s_; }
  /// The timings block of `steps` counted steps (peak resident memory read now).
  RunTimings timings(std::size_t steps) const;

 private:
  std::chrono::steady_clock::time_point t0_;
  double cpu0_ = 0, total_s_ = 0, max_s_ = 0;
};

/// The budget's drops as they happen: evictions.csv rows, the counts of drops and refusals, and
/// where the dropped landmarks were (map.png's marks, at most kMaxDroppedMarks).
class EvictionLog {
 public:
  static constexpr std::size_t kMaxDroppedMarks = 20000;  ///< a lifelong run drops millions
  void log(const std::vector<reducers::Eviction>& drops, report::RunOutputs& outputs);
  /// Landmarks dropped after holding a place in the map (evictions.csv rows but the refusals).
  std::size_t evictions() const { return evictions_; }
  /// Newcomers refused at admission (evictions.csv rows with reason refused).
  std::size_t refused() const { return refused_; }
  const std::vector<Eigen::Vector2d>& droppedMarks() const { return dropped_; }

 private:
  std::size_t evictions_ = 0, refused_ = 0;
  std::vector<Eigen::Vector2d> dropped_;
};

/// Relocalization coverage, followed step by step: which landmarks each step observed (by sensor
/// ID, or through the backend's association) against the map as it stands after the step's
/// drops (steps.csv's reloc_landmarks and reloc_coverage_so_far_pct), and the final map's
/// coverage of those steps (summary.json "relocalization").
class RelocCoverageTracking {
 public:
  /// `max_samples` = 0 keeps every step (metrics::RelocalizationTracker).
  RelocCoverageTracking(std::size_t min_landmarks, std::size_t max_samples);
  /// The landmarks the step's readings went to are in the map now (new ones included).
  void added(const std::vector<LandmarkId>& assoc);
  /// The map lost them.
  void removed(const std::vector<reducers::Eviction>& drops);
  /// The step's observations (`assoc`: the backend's association of `filtered`'s readings);
  /// returns how many landmarks of the map held after the step it observed.
  std::size_t observe(const Step& raw, const Step& filtered, const std::vector<LandmarkId>& assoc);
  double coverageSoFarPct() const { return tracker_.coverageSoFarPct(); }
  /// The tracked steps against `backend`'s landmarks now.
  FinalRelocCoverage finalCoverage(const Backend& backend) const;
  const metrics::RelocalizationTracker& tracker() const { return tracker_; }

 private:
  metrics::RelocalizationTracker tracker_;
  bool saw_ids_ = false, saw_idless_ = false;  ///< readings with / without sensor IDs
};

}  // namespace budget_slam::runs
