#pragma once
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/engine/LocalizationOutcome.h"
#include "budget_slam/engine/RunGiven.h"
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/MapAlignment.h"
#include "budget_slam/metrics/NeesAccumulator.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"

namespace budget_slam::runs {

/// summary.json "counts" (docs/OUTPUTS.md): filled by the run driver's step loop.
struct RunCounts {
  std::size_t steps = 0;                 ///< steps done
  std::size_t landmarks_final = 0;       ///< finite landmarks in the final map
  std::size_t landmarks_not_finite = 0;  ///< left out of the outputs
  std::size_t poses_not_finite = 0;      ///< left out of the outputs
  std::size_t landmarks_peak = 0;
  std::size_t landmarks_added = 0;
  std::size_t evictions = 0;  ///< drops of landmarks that held a place in the map
  std::size_t refused = 0;    ///< newcomers refused at admission
  std::size_t poses_kept = 0;
  std::size_t poses_marginalized = 0;
};

/// summary.json "timings": filled by the process probes around each step.
struct RunTimings {
  double steps_s = 0;       ///< wall time of the steps [s]
  double step_ms_mean = 0;  ///< NaN without a step [ms]
  double step_ms_max = 0;   ///< [ms]
  std::size_t peak_rss_bytes = 0;
};

/// summary.json "ground_truth": the errors against the rawlog's ground truth, the NEES and where
/// the ground truth's frame sits in the map's.
struct GroundTruthOutcome {
  std::string landmarks_file, path_file;  ///< the ground-truth files read
  metrics::GroundTruthErrors errors;
  metrics::NeesMean nees;
  std::optional<metrics::MapAlignment> alignment;
};

/// summary.json "relocalization": the final map's relocalization coverage.
struct RelocCoverageOutcome {
  metrics::RelocalizationCoverage coverage;
  std::string source;  ///< landmark_ids | own_association | reference_association | ...
  nlohmann::json details = nlohmann::json::object();  ///< extra fields
};

/// What a run, a comparison or a localization reports: how it ended and, block by block, what
/// each part of the run measured. One writer turns it into summary.json (SummaryJson.h).
struct RunOutcome {
  RunStatus status = RunStatus::Ok;
  ErrorKind kind = ErrorKind::None;
  std::string error;  ///< the one line saying why, when not ok ("" when ok)

  /// The run's own blocks, present once a run driver existed (a run that failed before it has
  /// none of them).
  struct Run {
    std::string backend, reducer;
    std::optional<std::size_t> cap;  ///< none: no cap
    RunCounts counts;
    RunTimings timings;
    nlohmann::json agreement = nlohmann::json::array();        ///< active vs shadow reducers
    nlohmann::json shadow_failures = nlohmann::json::array();  ///< failed shadow reducers
    RelocCoverageOutcome relocalization;
  };
  std::optional<Run> run;
  std::optional<GroundTruthOutcome> ground_truth;  ///< when the rawlog has ground truth
  std::vector<std::string> files_not_written;      ///< outputs a full disk kept out
  /// A localization's own blocks (start_pose, counts, localization, timings), once its filter
  /// existed, and its wake-up when it woke up on the map (LocalizationOutcome.h).
  std::optional<LocalizationOutcome> localization;
  std::optional<LocalizationWakeUp> wake_up;
  /// What the command was given and how far it got (rawlog, config, started, a comparison's run's
  /// metrics against the reference, the session state written, run's wake-up, ...): RunGiven.h.
  RunGiven given;

  bool ok() const { return status == RunStatus::Ok; }
  /// Ends the outcome as `s` with `kind` and `why` (a first failure stays).
  void fail(RunStatus s, ErrorKind k, std::string why) {
    status = s, kind = k, error = std::move(why);
  }
};

/// The exit code of `o` (exitCode(status, kind)).
inline int exitCode(const RunOutcome& o) { return exitCode(o.status, o.kind); }

}  // namespace budget_slam::runs
