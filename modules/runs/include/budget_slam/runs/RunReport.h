#pragma once
// What `run` hands back (runs::run, runs::runSlam): the typed outcome and what the caller shows.
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/engine/RunOutcome.h"

namespace budget_slam::runs {

/// What a run hands back besides its summary.json.
struct RunReport {
  RunOutcome outcome;
  /// The one stderr line when not ok (the error, and why summary.json could not be written when
  /// it could not); "" when ok.
  std::string line;
  std::vector<std::string> warnings;  ///< one line a failed shadow reducer
  std::size_t steps = 0;              ///< steps of this session
  std::optional<Pose2> final_pose;    ///< the robot at the end (a finished run)
  std::size_t landmarks = 0;          ///< in the map at the end
  std::string folder;                 ///< the output folder ("" if none)
};

}  // namespace budget_slam::runs
