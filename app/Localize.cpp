// budget-slam localize: a traversal localized in a run's final map (docs/OUTPUTS.md). The command
// line and the printing; the work is runs::localize (modules/runs/src/LocalizeRun.cpp).
#include <tclap/CmdLine.h>

#include <cmath>
#include <sstream>

#include "BudgetSlamApp.h"
#include "CommandLineFlags.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/runs/Localize.h"
#include "budget_slam/runs/RequestChecks.h"

namespace budget_slam::app {
namespace {

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << v;
  return o.str();
}

/// The summary lines of a localization that ended ok (stdout, unless --quiet).
void printLocalization(std::ostream& out, const runs::LocalizeReport& report) {
  const auto& l = *report.outcome.localization;
  const auto& m = l.localization;
  const auto& sc = m.score;
  out << "budget-slam localize: " << sc.steps << " steps in a map of " << report.map_landmarks
      << " landmarks, start from " << l.start.source << "\n";
  if (const auto& w = report.outcome.wake_up)
    out << "woken up at step " << w->result.step << " after " << w->steps_used << " step(s) ("
        << (w->result.by_ids ? "by landmark ids" : "by search") << ", " << fixed(w->time_ms, 1)
        << " ms)"
        << (w->error ? ", " + fixed(w->error->xy_m, 3) + " m and " + fixed(w->error->yaw_deg, 2) +
                           " deg from the truth"
                     : std::string())
        << "\n";
  if (!m.error_against.empty())
    out << "against the "
        << (m.error_against == "ground_truth" ? "ground truth" : "reference trajectory")
        << ": RMSE " << fixed(sc.rmse_m, 3) << " m, max " << fixed(sc.max_m, 3) << " m, lost "
        << fixed(sc.lost_pct, 1) << "% of the steps (error above " << fixed(m.lost_threshold_m, 2)
        << " m), NEES " << fixed(sc.nees_mean, 2) << "\n";
  out << "at least " << m.min_landmarks << " map landmarks observed at "
      << fixed(sc.coverage_pct, 1) << "% of the steps (mean " << fixed(sc.mean_landmarks, 2)
      << ")\n";
  if (m.diverged_at_step)
    out << "the filter was lost for good at step " << *m.diverged_at_step << "\n";
  out << "outputs in " << report.folder << "/\n";
}

}  // namespace

void BudgetSlamApp::initializeLocalize(const std::vector<std::string>& args) {
  request_ = std::monostate();
  help_.clear();
  CapturedUsage usage(  // outlives cmd, which only borrows it
      "   budget-slam run -c config.ini -i rawlogs/rooms.rawlog -o ROOMS\n"
      "   budget-slam localize -c config.ini --map ROOMS -i rawlogs/rooms_revisit.rawlog -o LOC\n"
      "      rooms' final map localizing another traversal of the same rooms\n");
  TCLAP::CmdLine cmd(
      "Localizes a traversal in the final map of an earlier run (its landmarks.csv) with MRPT's "
      "EKF, no landmark added, and measures the error, the share of steps lost and the map's "
      "coverage of the traversal",
      ' ', "0.1", true);
  cmd.setExceptionHandling(false);
  cmd.setOutput(&usage);
  TCLAP::ValueArg<std::string> config("c", "config", "ini file (MRPT style)", false, "", "file",
                                      cmd);
  TCLAP::ValueArg<std::string> map("", "map", "output folder of the run whose map is used", true,
                                   "", "RUN_DIR", cmd);
  TCLAP::ValueArg<std::string> rawlog("i", "input", "the traversal's rawlog", false, "", "rawlog",
                                      cmd);
  TCLAP::ValueArg<std::string> outdir("o", "out",
                                      "output folder; overrides [MappingApplication] "
                                      "logOutput_dir",
                                      false, "", "dir", cmd);
  TCLAP::ValueArg<std::string> start(
      "", "start-pose",
      "start pose in the map's frame, yaw in degrees (default: the traversal's ground truth "
      "through the map's alignment, or the reference trajectory)",
      false, "", "x,y,yaw", cmd);
  TCLAP::SwitchArg wake_up(
      "", "wake-up",
      "no start pose: find the robot on the map from the first steps' readings ([WakeUp]), then "
      "localize the rest of the traversal from there (also what happens when there is neither "
      "--start-pose nor ground truth nor a reference trajectory); not found: exit 3",
      cmd);
  TCLAP::ValueArg<std::string> reference(
      "", "reference-trajectory",
      "trajectory.tum (in the map's frame) to measure the error against when the traversal has "
      "no ground truth",
      false, "", "file.tum", cmd);
  TCLAP::ValueArg<std::string> max_steps(
      "", "max-steps",
      "localize the first N steps of the traversal (0: all); overrides [Localization] max_steps",
      false, "", "N", cmd);
  TCLAP::MultiArg<std::string> sets("", "set", "overrides any ini key", false, "Section.key=value",
                                    cmd);
  TCLAP::SwitchArg quiet("", "quiet", "no progress bar and no summary on stdout", cmd);
  TCLAP::SwitchArg force("", "force", "write into a non-empty output folder (deletes nothing)",
                         cmd);
  std::vector<std::string> argv = {"budget-slam localize"};  // the usage names the program
  argv.insert(argv.end(), args.begin() + 2, args.end());
  try {
    cmd.parse(argv);
  } catch (const TCLAP::ArgException& e) {
    throw UsageError(describe(e) + "; see budget-slam localize --help");
  } catch (const TCLAP::ExitException&) {
    help_ = usage.text;  // --help or --version
    return;
  }
  runs::LocalizeRequest r;
  r.common.config = config.getValue();
  r.map_dir = map.getValue();
  r.common.rawlog = rawlog.getValue();
  r.common.outdir = outdir.getValue();
  // Given empty, it is still given: refused below, never taken as "derive it".
  if (start.isSet()) r.start_pose = start.getValue();
  r.reference_trajectory = reference.getValue();
  r.wake_up = wake_up.getValue();
  r.common.sets = sets.getValue();
  r.common.quiet = quiet.getValue();
  r.common.force = force.getValue();
  // a bad start pose is part of the command line: exit 2 before anything is written
  try {
    runs::checkRequest(r);
    refuseEmptyValues({&config, &map, &rawlog, &outdir, &reference, &max_steps});
    if (max_steps.isSet()) r.common.max_steps = runs::parseMaxSteps(max_steps.getValue());
  } catch (const ConfigError& e) {
    throw runs::withHelpHint("localize", e);
  }
  request_ = std::move(r);
  loadConfigFile();
}

int BudgetSlamApp::runLocalize(const runs::LocalizeRequest& request) {
  runs::RequestContext context;
  context.params = params;
  context.config_text = std::move(config_text_);  // checked and parsed by runs::localize
  config_text_.reset();
  context.config_label = config_label_;
  runs::RunHooks hooks;
  hooks.progress_out = err;
  // [Report] progress_every_s, from the merged ini, is runs::localize's to set.
  hooks.progress = progressSettings(report::ReportOptions());
  hooks.on_step = on_step;
  hooks.note = [&](const std::string& line) {
    if (!request.common.quiet) *err << "budget-slam: " << line << std::endl;
  };
  hooks.warning = [&](const std::string& line) {
    *err << "budget-slam: warning: " << line << std::endl;
  };
  const runs::LocalizeReport report = runs::localize(request, std::move(context), hooks);
  const runs::RunOutcome& o = report.outcome;
  if (!report.line.empty()) {
    *err << "budget-slam: " << (o.status == runs::RunStatus::Interrupted ? "" : "error: ")
         << report.line << std::endl;
    return runs::exitCode(o);
  }
  if (!request.common.quiet) printLocalization(*out, report);
  return runs::exitCode(stdoutWritten(report.folder) ? runs::RunStatus::Ok
                                                     : runs::RunStatus::Failed);
}

}  // namespace budget_slam::app
