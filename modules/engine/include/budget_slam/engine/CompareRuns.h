#pragma once
#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/engine/RunDriver.h"
#include "budget_slam/engine/RunOutcome.h"

namespace budget_slam::runs {

/// One driver of `compare` and how it ended.
struct CompareRun {
  std::string name;  ///< reference, or the reducer's name (its folder's name)
  std::unique_ptr<RunDriver> driver;
  std::atomic<std::size_t> steps_done{0};
  std::atomic<bool> ended{false};  ///< its steps and end phase are over, however it ended
  RunStatus status = RunStatus::Ok;
  ErrorKind kind = ErrorKind::None;
  std::string error;
  /// What RunDriver::finish reported (none when it could not finish).
  std::optional<RunOutcome> result;
  bool ok() const { return status == RunStatus::Ok; }
};

/// Runs every driver over `steps` in `threads` threads (each taking whole runs), up to and
/// including its end phase (RunDriver::complete; `on_end_phase` is called first, from the worker
/// thread); `progress` hears the steps done over all runs. A stop request (Ctrl-C) ends each run
/// between two steps, or inside a step or the end phase (core/Cancellation.h): the run's status
/// is then interrupted; an error makes it failed. Returns when every run has ended; fewer threads
/// than asked for (core/WorkerThreads.h) is not an error: returns why, "" when all started.
/// `progress`'s ETA is compareEta's over each run's recent pace; `detail_after` ends its detail
/// (the phases that follow the runs, e.g. "then relocalization: 8 maps x 300 steps").
std::string runInThreads(std::vector<std::unique_ptr<CompareRun>>& runs,
                         const std::vector<Step>& steps, std::size_t threads,
                         const std::function<void()>& on_end_phase, ProgressReporter& progress,
                         const std::string& detail_after = "");

/// How far one run of a compare is, for the ETA.
struct RunPace {
  std::size_t steps_left = 0;  ///< 0 when it ended
  /// [s] a step, over the run's recent steps (its cost grows with its map); NaN before any.
  double step_s = std::numeric_limits<double>::quiet_NaN();
};

/// The time left [s] for `runs` on `threads` threads: at least the longest run's time left (a run
/// is on one thread), and at least all the work left shared by the threads. A run not measured
/// yet (queued) is given the median pace of those measured; NaN when none is.
double compareEta(const std::vector<RunPace>& runs, std::size_t threads);

/// A note for a compare whose unreduced EKF reference will be long: its map holds every landmark
/// the steps read (`landmarks`, their distinct ids) and each EKF step costs the square of that.
/// "" when `backend` is not ekf or the map stays under `kLargeEkfMap` landmarks.
std::string largeReferenceNote(const std::string& backend, std::size_t landmarks);
constexpr std::size_t kLargeEkfMap = 300;  ///< [landmarks] (576 took 10 min on one core)

/// The distinct landmark ids the readings of `steps` carry (0 without ids).
std::size_t distinctLandmarkIds(const std::vector<Step>& steps);

/// True when no reading of `steps` carries a sensor landmark ID.
bool withoutLandmarkIds(const std::vector<Step>& steps);

/// For a rawlog without sensor IDs: the final map of `run` (after complete()) against the steps'
/// observations as the `reference` run associated them: each of its landmarks paired with a
/// reference landmark (metrics::matchLandmarks). Returns the relocalization coverage
/// RunDriver::finish should report.
FinalRelocCoverage relocCoverageThroughReference(const RunDriver& reference, const RunDriver& run,
                                                 double gate_chi2);

/// "interrupted by SIGINT<where> after step k" (or "before the first step") for run `r`.
std::string interruptedLine(const CompareRun& r, const char* where);

}  // namespace budget_slam::runs
