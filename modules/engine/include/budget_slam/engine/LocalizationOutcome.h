#pragma once
// The blocks of a localization's outcome (`budget-slam localize`, `compare --relocalize`), typed:
// runs::writeSummary turns them into summary.json's start_pose, counts, localization, timings and
// wake_up (docs/OUTPUTS.md "budget-slam localize").
#include <cstddef>
#include <limits>
#include <optional>
#include <string>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/metrics/LocalizationScore.h"
#include "budget_slam/wakeup/GlobalLocalizer.h"

namespace budget_slam::runs {

/// summary.json "start_pose": where the filter started, and from what.
struct LocalizationStart {
  PoseEstimate pose;   ///< in the map's frame; the covariance the filter started with
  std::string source;  ///< "--start-pose", "ground truth", "reference trajectory", "wake-up"
};

/// summary.json "counts" of a localization.
struct LocalizationCounts {
  std::size_t steps = 0;          ///< steps localized
  std::size_t map_landmarks = 0;  ///< distinct landmarks of the map
};

/// summary.json "timings" of a localization.
struct LocalizationTimings {
  double steps_s = 0;                                              ///< wall time of the steps [s]
  double step_ms_mean = std::numeric_limits<double>::quiet_NaN();  ///< NaN without a step [ms]
};

/// summary.json "localization": the settings the score was made with, the score, and what the
/// filter did with the readings.
struct LocalizationMeasures {
  std::size_t min_landmarks = 0;  ///< [Metrics] reloc_min_landmarks: the coverage's k
  double lost_threshold_m = 0;    ///< [Localization] lost_threshold [m]
  std::string error_against;      ///< "ground_truth", "reference_trajectory", "" (none)
  std::string error_file;         ///< the file the truth came from
  double success_xy_m = 0, success_yaw_deg = 0;  ///< [Localization] success_xy, success_yaw_deg
  double place_size_m = 0;                       ///< the places' cell side [m]
  std::size_t heading_sectors = 0;
  /// Where steps are scored: everywhere (no mapping path), else the cells of `mapped_cell_m`
  /// within `mapped_reach_m` of the mapping path (metrics::MappedArea).
  bool mapped_everywhere = true;
  double mapped_cell_m = 0, mapped_reach_m = 0;
  metrics::LocalizationScore score;
  std::size_t readings_used = 0, readings_gated = 0, recoveries = 0, readings_not_in_map = 0,
              readings_consistent_with_map = 0;
  std::optional<StepIndex> diverged_at_step;  ///< the filter lost for good from this step on
  std::string diverged_why;
};

/// A localization's own blocks.
struct LocalizationOutcome {
  LocalizationStart start;
  LocalizationCounts counts;
  LocalizationMeasures localization;
  LocalizationTimings timings;
};

/// summary.json "wake_up" of `localize` (docs/OUTPUTS.md "localize --wake-up"): how the robot was
/// found on the map, or why not.
struct LocalizationWakeUp {
  bool asked = false;           ///< --wake-up given (else: no start pose to be had)
  wakeup::WakeUpResult result;  ///< status, reason, pose, covariance, step, hypotheses, ...
  std::string why_not_found;    ///< one line, "" when found
  std::size_t max_steps = 0;    ///< [WakeUp] max_steps
  std::size_t steps_used = 0;   ///< steps read to find the robot (not localized)
  double time_ms = 0;           ///< wall time [ms]
  /// The pose found against the truth at its step, when there is a truth there.
  struct Error {
    std::string against;  ///< ground_truth | reference_trajectory
    double xy_m = 0, yaw_deg = 0;
    bool within_success = false;  ///< within [Localization] success_xy and success_yaw_deg
  };
  std::optional<Error> error;
  bool found() const { return result.status == wakeup::WakeUpStatus::Found; }
};

}  // namespace budget_slam::runs
