#pragma once
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/engine/RegistryListing.h"
#include "budget_slam/reducers/BudgetOptions.h"
#include "budget_slam/report/ReportOptions.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/Request.h"

namespace budget_slam::app {

/// budget-slam's version (--version, the session state's writer "budget-slam <version>").
inline constexpr const char* kVersion = runs::kVersion;

/// The budget-slam application: a thin main() calls initialize() and run(); tests drive it with an
/// in-memory config (`params`) and a temporary output folder, as MRPT's KFSLAMApp.
class BudgetSlamApp {
 public:
  /// Parses the command line (args[0] = program name) and reads the -c file (run() checks and
  /// parses it into `params`). Throws UsageError on a bad command line (main exits 2), ConfigError
  /// when -c cannot be read (missing, a folder, over 1 MiB). --help and --version only keep their
  /// text for run().
  void initialize(const std::vector<std::string>& args);
  void initialize(int argc, const char* const* argv);

  /// Runs the command. Returns the process exit code (0 ok, 1 failed, 130 interrupted); never
  /// throws: errors become one line on `err` and, when the output folder exists, summary.json.
  /// After --help or --version: prints that text once on `out` and returns 0.
  int run();

  mrpt::config::CConfigFileMemory params;  ///< the ini, before sidecar, --set and flags (tests may
                                           ///< set it instead of giving -c)
  std::ostream* out = nullptr;             ///< summary lines (default std::cout)
  std::ostream* err = nullptr;             ///< errors and progress (default std::cerr)
  /// Called after each step of `run` (progress observers; tests use it to press Ctrl-C).
  std::function<void(StepIndex)> on_step;
  /// Called once the steps are done, before the end phase (the reducer's end-of-run event, the
  /// graph's final solve, the outputs); tests use it to press Ctrl-C there. compare calls it once
  /// a run, from its worker threads.
  std::function<void()> on_end_phase;
  /// Progress of run, compare and localize (Python's progress=), whatever stderr shows; called
  /// from the calling thread, at most 5 times a second and once at the end; must not throw.
  ProgressCallback on_progress;

 private:
  int runRun(const runs::RunRequest& request);
  int runCompare(const runs::CompareRequest& request);
  /// What a command runs with besides its request: params, or the -c text still to parse (handed
  /// over: the command parses it), its label and the writer.
  runs::RequestContext requestContext();
  /// Progress on `err`, on_step, on_end_phase, notes (unless --quiet) and warnings on `err`.
  runs::RunHooks requestHooks() const;
  /// Flushes `out`. False, after one line on `err`, when stdout cannot take it (a closed pipe):
  /// the command then exits 1, its outputs (in `outdir`, when given) complete.
  bool stdoutWritten(const std::string& outdir);
  /// Checks and parses the -c text read by initialize() into `params` (core/IniText.h): a
  /// binary file, prose, a duplicated key or a failed ${...} is a ConfigError naming the line.
  void loadConfig();
  int runLocalize(const runs::LocalizeRequest& request);
  /// localize's command line (Localize.cpp).
  void initializeLocalize(const std::vector<std::string>& args);
  /// Reads -c (or ./config.ini when params is empty) for loadConfig(): missing, a folder or over
  /// 1 MiB is a command-line error.
  void loadConfigFile();

  /// Where progress goes: a bar on a terminal, lines every [Report] progress_every_s elsewhere,
  /// nothing with --quiet; and on_progress.
  ProgressSettings progressSettings(const report::ReportOptions& report) const;

  /// The command's flags (no command parsed yet: --help, --version, --list).
  std::variant<std::monostate, runs::RunRequest, runs::CompareRequest, runs::LocalizeRequest>
      request_;
  /// What every command's request holds (an empty one before a command is parsed).
  const runs::RequestCommon& common() const;
  std::string config_label_ = "config";
  std::optional<std::string> config_text_;  ///< the -c file, until loadConfig()
  bool config_defaulted_ = false;           ///< no -c: ./config.ini was read
  std::string help_;                        ///< usage or version text to print instead of running
};

}  // namespace budget_slam::app
