#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "RunDriver.h"
#include "RunResult.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Step.h"

namespace budget_slam::app {

/// One driver of `compare` and how it ended.
struct CompareRun {
  std::string name;  ///< reference, or the reducer's name (its folder's name)
  std::unique_ptr<RunDriver> driver;
  std::atomic<std::size_t> steps_done{0};
  std::string status = "ok", error;
  /// What RunDriver::finish reported (none when it could not finish).
  std::optional<RunResult> result;
};

/// Runs every driver over `steps` in `threads` threads (each taking whole runs), up to and
/// including its end phase (RunDriver::complete; `on_end_phase` is called first, from the worker
/// thread); `progress` hears the steps done over all runs. A stop request (Ctrl-C) ends each run
/// between two steps, or inside a step or the end phase (core/Cancellation.h): the run's status
/// is then interrupted; an error makes it failed. Returns when every run has ended.
void runInThreads(std::vector<std::unique_ptr<CompareRun>>& runs, const std::vector<Step>& steps,
                  std::size_t threads, const std::function<void()>& on_end_phase,
                  ProgressReporter& progress);

/// "interrupted by SIGINT<where> after step k" (or "before the first step") for run `r`.
std::string interruptedLine(const CompareRun& r, const char* where);

}  // namespace budget_slam::app
