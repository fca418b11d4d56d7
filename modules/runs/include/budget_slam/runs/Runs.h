#pragma once
// A run from its typed specification (docs/ARCHITECTURE.md "A run"): runs::run (Commands.h)
// builds the specification from a request and hands it to runSlam.
#include <mrpt/config/CConfigFileMemory.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/BackendRegistry.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/engine/RunDriver.h"
#include "budget_slam/runs/RunHooks.h"
#include "budget_slam/runs/RunReport.h"
#include "budget_slam/session/SessionState.h"

namespace budget_slam::runs {

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
  RunGiven given;
};

/// Runs SLAM under the budget over spec.rawlog into spec.outdir (docs/ARCHITECTURE.md "A run"):
/// the output folder, config_used.ini, the step loop (RunDriver), the session state, the end
/// phase and every output, summary.json last. Never throws: every failure is in the outcome
/// (failed or interrupted), with the outputs of the steps done written.
RunReport runSlam(const RunSpec& spec, const RunHooks& hooks);

}  // namespace budget_slam::runs
