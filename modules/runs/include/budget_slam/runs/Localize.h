#pragma once
// `budget-slam localize` behind the run layer's API (docs/ARCHITECTURE.md "Modules"): a typed
// request in, a typed report out, as runs::run and runs::compare (Commands.h). app/Localize.cpp
// parses the command line into the LocalizeRequest and prints the report; the Python module
// (budget_slam.localize) fills the same LocalizeRequest from its arguments.
#include <string>
#include <vector>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/runs/Request.h"
#include "budget_slam/runs/RunHooks.h"

namespace budget_slam::runs {

/// What a localization hands back besides its output folder. The typed blocks are the outcome's
/// (RunOutcome::localization: start pose, counts, score, timings, once the filter existed;
/// RunOutcome::wake_up once the robot was looked for on the map).
struct LocalizeReport {
  RunOutcome outcome;  ///< ok, failed, interrupted, or not_found (the wake-up found nothing)
  /// The one stderr line when not ok (the error, and why summary.json could not be written when
  /// it could not); "" when ok. Not found: "wake-up: <why>; no pose is guessed".
  std::string line;
  /// Lines for stderr as "warning: <line>": what the configuration's merge replaced, and a map
  /// and a traversal that share no place.
  std::vector<std::string> warnings;
  std::string folder;             ///< the output folder ("" when none was made)
  std::size_t map_landmarks = 0;  ///< landmarks of the map read (its landmarks.csv rows)
};

/// Localizes request.common.rawlog in the final map of the run in request.map_dir
/// (docs/OUTPUTS.md "budget-slam localize"): the configuration, the output folder and
/// config_used.ini, the map folder, the reference trajectory, the traversal read whole, its
/// ground truth, the start pose (given, derived, or woken up on the map: wakeup::wakeUpOver), the
/// filter over the steps (Localizer), and every output, summary.json last. Never throws: every
/// failure is in the report (failed, interrupted, not_found), with the outputs of the steps done
/// written. context: the ini (or the -c text, checked and parsed here: a bad text is the
/// localization's failure, said in its output folder) and its label. hooks: progress of the
/// reading and of the steps, on_step after each step (on_end_phase is not called), note for
/// "no start pose (...): waking up on the map", warning for each of report.warnings as it
/// arises; the progress lines' interval is the merged ini's [Report] progress_every_s.
LocalizeReport localize(const LocalizeRequest& request, RequestContext context,
                        const RunHooks& hooks);

/// --start-pose "x,y,yaw" (metres, metres, degrees) -> pose (yaw in radians): three finite
/// numbers, x and y within limits::kMaxCoordinate, yaw within limits::kMaxAngle. Throws
/// ConfigError naming the flag.
Pose2 parseStartPose(const std::string& text);

}  // namespace budget_slam::runs
