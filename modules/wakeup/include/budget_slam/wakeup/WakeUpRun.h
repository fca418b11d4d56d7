#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/wakeup/GlobalLocalizer.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

/// The sensor's reading noise as the backends read it: [RangeBearingKFSLAM] std_sensor_range
/// [m] (default 0.1) and std_sensor_yaw_deg [deg] (default 0.5), the latter in radians.
ReadingNoise readingNoiseOf(const mrpt::config::CConfigFileBase& ini);

/// One wake-up from a stream of steps, as a command reports it (`localize --wake-up`, `run
/// --resume --wake-up`): the localizer's result, the steps it read and its wall time.
struct WakeUpRun {
  WakeUpResult result;
  std::size_t steps_read = 0;  ///< steps given to the localizer (at most [WakeUp] max_steps)
  double wall_ms = 0;          ///< from the localizer's construction to its last step [ms]
  bool found() const { return result.status == WakeUpStatus::Found; }
  /// When not found: one line saying so, with the steps read and why, e.g. "the robot was not
  /// found on the map in 10 steps (ambiguous: 6 landmarks agree with the best pose, 5 with
  /// another)" or "... (not_found, too_few_landmarks: 1 map landmark(s) seen, 2 needed)".
  /// "" when found.
  std::string whyNotFound(const WakeUpOptions& options) const;
};

/// Runs a GlobalLocalizer on `map` over the steps `next` returns (nullptr: no more), until it
/// finishes (found, or [WakeUp] max_steps read) or the steps run out. Never a guessed pose: an
/// ambiguous or uncertain outcome is not found.
WakeUpRun wakeUpOver(const std::vector<LandmarkView>& map, const std::function<const Step*()>& next,
                     const WakeUpOptions& options, const ReadingNoise& noise);

/// The error of a found pose against the truth at the same step: metres and degrees.
struct WakeUpError {
  double xy_m = 0;
  double yaw_deg = 0;
};
WakeUpError wakeUpError(const PoseEstimate& found, const Pose2& truth);

}  // namespace budget_slam::wakeup
