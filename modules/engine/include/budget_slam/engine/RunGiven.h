#pragma once
// What a command was given and how far it got: summary.json's top-level keys beside the blocks the
// run measured (docs/OUTPUTS.md "summary.json"). One field a key; a field is written only when
// set, by the one writer (SummaryJson.h).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/metrics/ReferenceMetrics.h"

namespace budget_slam::runs {

/// summary.json "session_state" of a run: whether session_state.txt was written, and why not.
struct SessionStateWritten {
  bool written = false;
  std::string why;  ///< the one line of the failure ("" when written; then not in the file)
};

/// summary.json "wake_up" of `run --resume --wake-up`: the robot looked for on the saved map
/// (RunSession.h wakeUpOnMap). A localization's wake-up is RunOutcome::wake_up instead.
struct ResumeWakeUp {
  std::string status;         ///< wakeup::statusName: found, not_found, ...
  std::string reason;         ///< wakeup::reasonName ("" when found)
  bool by_ids = false;        ///< readings paired with the map by landmark id (else by search)
  std::size_t steps = 0;      ///< steps read to find it
  std::size_t landmarks = 0;  ///< distinct map landmarks seen
  std::size_t inliers = 0;    ///< readings that agree with the pose
  double time_ms = 0;         ///< wall time of the wake-up [ms]
  std::optional<std::array<double, 3>> pose;  ///< x [m], y [m], yaw [deg], when found
};

/// What a run, a comparison's run, a comparison or a localization was given, and how far it got.
/// Every field is a top-level key of summary.json, written when set.
struct RunGiven {
  std::optional<std::string> command;      ///< "localize" (run and compare write none)
  std::optional<std::string> rawlog;       ///< -i, or the ini's rawlog once resolved
  std::optional<std::string> sidecar_ini;  ///< the rawlog's sidecar ini applied ("" none)
  std::optional<std::string> config;       ///< the ini's label (-c's path, "config", ...)
  /// Whether a step was done: false, the next command into the folder replaces its files.
  std::optional<bool> started;
  std::optional<std::string> earlier_run_moved_to;   ///< --force: where an earlier run went
  std::optional<std::string> resumed_from;           ///< run --resume RUN_DIR
  std::optional<ResumeWakeUp> wake_up;               ///< run --resume --wake-up
  std::optional<SessionStateWritten> session_state;  ///< run: session_state.txt
  std::optional<std::string> run;  ///< a comparison's run: its name (reference, mi, mi_seed3)
  /// A comparison's run against the unreduced reference (Choudhary et al. Sec. V-B).
  std::optional<metrics::ReferenceMetrics> reference_metrics;
  std::optional<std::size_t> runs;                  ///< compare: runs made, the reference too
  std::optional<std::vector<std::uint64_t>> seeds;  ///< compare: --seeds (empty: the ini's)
  std::optional<std::size_t> steps;                 ///< compare: steps read from the rawlog
  std::optional<std::size_t> threads;               ///< compare: threads the runs took
  std::optional<std::string> map;                   ///< localize: --map RUN_DIR
  std::optional<std::string> map_status;  ///< localize: the mapping run's status ("" none)

  /// Every field `over` sets replaces this one's (as a later key replaces an earlier one).
  void update(const RunGiven& over);
};

}  // namespace budget_slam::runs
