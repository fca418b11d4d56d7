#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <map>
#include <string>

#include "budget_slam/session/SessionState.h"

namespace budget_slam::app {

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

}  // namespace budget_slam::app
