#pragma once
// summary.json (docs/OUTPUTS.md "summary.json"): the one writer, from a RunOutcome, and the one
// reader, used by `localize --map` (modules/localization/src/MapFolder.cpp), the Python module and,
// through the Python module's key list, the experiment scripts.
#include <nlohmann/json.hpp>
#include <string>

#include "budget_slam/engine/RunOutcome.h"

namespace budget_slam::runs {

/// summary.json's text of `o`: status, error, the run's blocks (backend, reducer, cap, counts,
/// timings, agreement, shadow_failures, relocalization) when there was a run, ground_truth,
/// files_not_written, a localization's blocks (start_pose, counts, localization, timings) and
/// its wake_up, then the keys of `o.given` that it sets (RunGiven.h).
nlohmann::json summaryJson(const RunOutcome& o);

/// Writes summaryJson(o) to `path` atomically (report::writeSummaryJson). Throws Error naming
/// the file when it cannot be written.
void writeSummary(const std::string& path, const RunOutcome& o);

/// A summary.json read back.
struct SummaryFile {
  nlohmann::json json;      ///< the whole document
  std::string status_text;  ///< "status" as written, cut to a printable excerpt ("" if absent)
  /// The outcome as far as the document holds it: status (failed when it is none of RunStatus's
  /// words; the kind of a failure read back is internal: the file does not say it),
  /// error, the run's blocks, ground_truth (with map_alignment, checked), files_not_written,
  /// the given keys (RunGiven.h; run's wake_up and reference_metrics stay in `json` only). A
  /// number that is null or not a number reads as NaN.
  RunOutcome outcome;
};

/// summary.json's top-level keys the writer knows (the rest are a caller's `given`): the list
/// the experiment scripts read against (python: budget_slam.summary_keys()).
const std::vector<std::string>& summaryKeys();

/// Reads `path`, bounded (at most 1 MiB, nested at most 16 deep). Throws InputError, one line
/// naming the file: "X: not valid JSON (...)", "X: not a budget-slam summary (not an object)",
/// "X: ground_truth.map_alignment.x is not a finite number", "... is out of range", ...
SummaryFile readSummary(const std::string& path);
/// The same from a parsed document; `label` names it in errors.
SummaryFile summaryFromJson(nlohmann::json j, const std::string& label);

}  // namespace budget_slam::runs
