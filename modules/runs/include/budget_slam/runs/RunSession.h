#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <map>
#include <string>

#include "budget_slam/engine/RunGiven.h"

#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/session/SessionState.h"

namespace budget_slam::runs {

/// The options a resumed run must share with the session it continues ("Section.key" -> value of
/// the merged ini): every key but those of [Report], [Metrics], [WakeUp] and the
/// [MappingApplication] keys that name this session's files and length (rawlog, output folder,
/// ground truth, max_steps, scenes). docs/OUTPUTS.md "Session state".
std::map<std::string, std::string> resumeOptions(const mrpt::config::CConfigFileBase& ini);

/// Reads RUN_DIR/session_state.txt for `run --resume` and checks it against the run about to
/// start: the backend, then every resume option. Throws InputError (the file) or ConfigError
/// (a mismatch: "--resume R: [LandmarkBudget] max_landmarks = 40, the saved session had 50"),
/// one line, before anything is written.
session::SessionState loadResumeState(const std::string& run_dir, const std::string& backend,
                                      const std::map<std::string, std::string>& options);

/// What `run --resume --wake-up` found (summary.json "wake_up").
struct WakeUpOutcome {
  bool found = false;
  std::size_t steps = 0;  ///< steps read to find it (their readings localize, they are not mapped)
  std::string why;        ///< when not found: one line
  ResumeWakeUp block;     ///< summary.json "wake_up"
};

/// Finds the robot on the saved map from the first steps of rc.rawlog after `skip` steps
/// (wakeup::GlobalLocalizer, [WakeUp]); when found, replaces the state's robot by the pose found
/// and its covariance, uncorrelated with the map, and marks it session::RobotStart::Placed (the
/// backends start a new chain on the map): the hand-over to the filter (docs/ALGORITHMS.md
/// "Waking up on a saved map"). Ambiguous is never a pose.
WakeUpOutcome wakeUpOnMap(const RunConfig& rc, session::SessionState& state, std::size_t skip);

}  // namespace budget_slam::runs
