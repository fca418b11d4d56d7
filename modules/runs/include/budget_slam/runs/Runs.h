#pragma once
// The run layer's API (docs/ARCHITECTURE.md "Modules"): a typed specification in, a typed
// outcome out. app/ parses the command line into a specification, prints what comes back and
// exits with runs::exitCode; the Python module binds the same calls.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/math/TPose2D.h>

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "budget_slam/core/BackendRegistry.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/runs/RunDriver.h"
#include "budget_slam/runs/RunOutcome.h"
#include "budget_slam/session/SessionState.h"

namespace budget_slam::runs {

/// How the caller follows a run: where progress goes, what it hears after each step and before
/// the end phase, and where notes go (a note is one line; the caller decides whether to show it).
struct RunHooks {
  std::ostream* progress_out = nullptr;  ///< the progress bar or lines (none: no progress)
  ProgressSettings progress;
  std::function<void(StepIndex)> on_step;        ///< after each step (tests press Ctrl-C there)
  std::function<void()> on_end_phase;            ///< once the steps are done, before the end phase
  std::function<void(const std::string&)> note;  ///< "<folder> held an earlier run; ...", ...
  /// A warning as it arises (one line without "warning: "): a sidecar key over the ini's, fewer
  /// threads than asked, a failed shadow reducer (runs::run and runs::compare; runSlam hands its
  /// warnings back in RunReport::warnings instead).
  std::function<void(const std::string&)> warning;
};

/// One `run`, typed: the merged ini and what was read from it and the command line.
struct RunSpec {
  mrpt::config::CConfigFileMemory ini;        ///< merged; written as config_used.ini
  const BackendRegistry* backends = nullptr;  ///< where spec.driver.backend is built from
  DriverSpec driver;
  std::string rawlog;                                      ///< resolved path
  std::string ground_truth_file, ground_truth_file_robot;  ///< "" = next to the rawlog
  std::string outdir;
  bool force = false;          ///< write into a non-empty output folder
  std::size_t max_steps = 0;   ///< 0 = the whole rawlog
  std::size_t skip_steps = 0;  ///< the rawlog's first steps left unread (--skip-steps)
  /// A saved session to continue (read and checked by the caller), and the steps the wake-up
  /// read to find the robot (not mapped).
  std::optional<session::SessionState> resumed;
  std::size_t wake_up_steps = 0;
  std::map<std::string, std::string> resume_options;  ///< into the session state written
  std::string writer;  ///< "budget-slam <version>", the session state's writer
  /// What the run was given, into summary.json (rawlog, sidecar_ini, config, resumed_from, ...).
  nlohmann::json given = nlohmann::json::object();
};

/// What a run hands back besides its summary.json.
struct RunReport {
  RunOutcome outcome;
  /// The one stderr line when not ok (the error, and why summary.json could not be written when
  /// it could not); "" when ok.
  std::string line;
  std::vector<std::string> warnings;              ///< one line a failed shadow reducer
  std::size_t steps = 0;                          ///< steps of this session
  std::optional<mrpt::math::TPose2D> final_pose;  ///< the robot at the end (a finished run)
  std::size_t landmarks = 0;                      ///< in the map at the end
  std::string folder;                             ///< the output folder ("" if none)
};

/// Runs SLAM under the budget over spec.rawlog into spec.outdir (docs/ARCHITECTURE.md "A run"):
/// the output folder, config_used.ini, the step loop (RunDriver), the session state, the end
/// phase and every output, summary.json last. Never throws: every failure is in the outcome
/// (failed or interrupted), with the outputs of the steps done written.
RunReport runSlam(const RunSpec& spec, const RunHooks& hooks);

}  // namespace budget_slam::runs
