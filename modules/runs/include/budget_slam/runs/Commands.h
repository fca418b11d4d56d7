#pragma once
// `run` and `compare` from a typed request (docs/ARCHITECTURE.md "A run", "A compare"): what the
// command line and the Python module both call. A request is checked by runs::checkRequest
// first (RequestChecks.h); these calls never throw, and every failure is in the report they
// return, with the lines to show and the files of the work already done written.
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/report/ComparisonTable.h"
#include "budget_slam/runs/CompareOutcome.h"
#include "budget_slam/runs/Request.h"
#include "budget_slam/runs/RunHooks.h"
#include "budget_slam/runs/RunReport.h"

namespace budget_slam::runs {

/// `run` (docs/ARCHITECTURE.md "A run"): the merged configuration (loadRunConfig; a bad one
/// ends the run before it starts, saying why in summary.json when the output folder can take
/// it), the session to resume read and checked before anything is written (a mismatch is one
/// line and no folder), the wake-up on its map, then runSlam. Progress lines come every
/// [Report] progress_every_s (hooks.progress.line_every_s is replaced by it). Warnings go to
/// hooks.warning as they arise (also those of runSlam's report), notes to hooks.note. The
/// report's `line` is the one line of a run that did not end ok.
RunReport run(const RunRequest& request, RequestContext context, const RunHooks& hooks);

/// One run of a comparison as it ended.
struct ComparedRun {
  std::string name;  ///< comparison.csv's `run`: its folder under the comparison's
  /// The outcome its summary.json was written from (RunDriver::finish); none when the run could
  /// not be finished.
  std::optional<RunOutcome> summary;
};

/// What `compare` hands back.
struct CompareReport {
  /// Status, error kind and first error (the top summary.json's), and the lines to show once
  /// the comparison ended, in order ("error: ..." a run or localization that failed, the line
  /// of one interrupted, "warning: ..." a failed shadow reducer; a comparison that could not
  /// start has its one line here).
  CompareOutcome outcome;
  /// The top summary.json's outcome as it was written (or would have been, when the folder could
  /// not take it): status, error, files not written, what the comparison was given.
  RunOutcome summary;
  std::vector<report::ComparisonRow> rows;  ///< comparison.csv's rows, the reference first
  std::vector<ComparedRun> runs;            ///< every run, in the rows' order
  std::string markdown;  ///< comparison.md (and the offline optimum's table), "" if not made
  std::string folder;    ///< the output folder, "" when none was made
  bool started = false;  ///< the runs started: the comparison reached its outputs
};

/// `compare` (docs/ARCHITECTURE.md "A compare"): the configuration, the output folder, the
/// rawlog read once, the reference and a run a reducer (and seed) in threads, every run ended
/// against the reference, --relocalize, comparison.csv/.md, the offline optimum, the figure and
/// the top summary.json last. hooks.on_end_phase is called once a run, from its thread; on_step
/// is not called. Progress, warnings and notes as run().
CompareReport compare(const CompareRequest& request, RequestContext context, const RunHooks& hooks);

}  // namespace budget_slam::runs
