#include "BudgetSlamApp.h"

#include <tclap/CmdLine.h>

#include <cmath>
#include <iostream>
#include <sstream>
#include <type_traits>

#include "CommandLineFlags.h"
#include "ListCommand.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/StopSignals.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/report/Figure.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/RequestChecks.h"
#include "budget_slam/runs/Runs.h"

namespace budget_slam::app {
namespace {

/// `budget-slam --help`: the commands, and the reducers from the registry.
std::string topLevelHelp() {
  std::string text =
      "budget-slam: landmark SLAM on an MRPT rawlog under a landmark budget\n\n"
      "USAGE:\n\n"
      "   budget-slam run     -c config.ini [-i in.rawlog] [-o outdir] [--reducer NAME]\n"
      "                       [--cap N|none] [--backend " +
      runs::builtinBackends().joinedNames("|") +
      "] [--set Section.key=value]...\n"
      "   budget-slam compare -c config.ini [-i in.rawlog] [-o outdir] [--reducers a,b,c]\n"
      "                       [--cap N|none] [--threads N] [--relocalize a.rawlog,b.rawlog]\n"
      "                       [--reference-trajectory ref.tum] [...]\n"
      "   budget-slam localize -c config.ini --map RUN_DIR -i other.rawlog [-o outdir]\n"
      "                       [--start-pose x,y,yaw] [--reference-trajectory ref.tum] [...]\n"
      "   budget-slam <command> --help    every option of a command\n"
      "   budget-slam --list reducers|backends [--json]    names, summaries, options, defaults\n"
      "   budget-slam --version\n\n"
      "Reducers:\n\n";
  for (const auto* e : reducers::builtinReducers().entries())
    text += "   " + e->name + std::string(e->name.size() < 14 ? 14 - e->name.size() : 1, ' ') +
            e->summary + "\n";
  return text +
         "\nExit codes: 0 ok, 1 failed run, 2 bad command line, 3 not found on the map (localize\n"
         "--wake-up), 130 interrupted.\n";
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string fixed(double v, int digits) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << v;
  return o.str();
}

}  // namespace

void BudgetSlamApp::initialize(int argc, const char* const* argv) {
  initialize(std::vector<std::string>(argv, argv + argc));
}

void BudgetSlamApp::initialize(const std::vector<std::string>& args) {
  request_ = std::monostate();
  help_.clear();
  const std::string command = args.size() >= 2 ? args[1] : "";
  if (command == "--help" || command == "-h") {
    help_ = topLevelHelp();
    return;
  }
  if (command == "--version") {
    help_ = std::string("budget-slam version ") + kVersion + "\n";
    return;
  }
  if (command == "--list") return void(help_ = listCommand(args));
  if (command == "localize") return initializeLocalize(args);
  if (command != "run" && command != "compare")
    throw UsageError((command.empty() ? std::string("expected a command, run, compare or localize")
                                      : "unknown command '" + command +
                                            "' (expected run, compare or localize)") +
                     "; see budget-slam --help");
  const bool compare = command == "compare";

  CapturedUsage usage(  // outlives cmd, which only borrows it
      compare
          ? "   budget-slam compare -c config.ini -o CMP --cap 50\n"
            "      every reducer and the unreduced reference on config.ini's rawlog:\n"
            "      CMP/comparison.md, comparison.csv, comparison.png, a folder a run\n"
            "   budget-slam compare -c config.ini -i rawlogs/kf-slam_demo.rawlog --reducers "
            "random,mi --cap 20 --seeds 1:5 -o CMP5\n"
            "      each reducer with seeds 1 to 5, and the mean and std over the seeds\n"
            "   budget-slam compare -c config.ini -i rawlogs/rooms.rawlog --cap 50 --relocalize "
            "rawlogs/rooms_revisit.rawlog -o CMPR\n"
            "      every final map also localizes another traversal of the same place\n"
          : "   budget-slam run -c config.ini -o OUT\n"
            "      config.ini's rawlog, reducer and cap\n"
            "   budget-slam run -c config.ini -i rawlogs/kf-slam_demo.rawlog -o OUT2 --reducer "
            "mi --cap 20 --set LandmarkBudget.seed=3\n"
            "   budget-slam run -c config.ini -i rawlogs/victoria_park.rawlog --backend graph "
            "--max-steps 1000 -o OUT3\n");
  TCLAP::CmdLine cmd(compare ? "Runs every reducer and the unreduced reference on one rawlog and "
                               "compares them"
                             : "Runs landmark SLAM on a rawlog under a landmark budget",
                     ' ', kVersion, true);
  cmd.setExceptionHandling(false);
  cmd.setOutput(&usage);
  TCLAP::ValueArg<std::string> config("c", "config", "ini file (MRPT style)", false, "", "file",
                                      cmd);
  TCLAP::ValueArg<std::string> rawlog("i", "input",
                                      "input rawlog; overrides "
                                      "[MappingApplication] rawlog_file",
                                      false, "", "rawlog", cmd);
  TCLAP::ValueArg<std::string> outdir("o", "out",
                                      "output folder; overrides "
                                      "[MappingApplication] logOutput_dir",
                                      false, "", "dir", cmd);
  TCLAP::ValueArg<std::string> reducer(
      "", "reducer",
      "reducer, one of " + reducers::builtinReducers().joinedNames(", ") +
          " (budget-slam --help says what each does); overrides [LandmarkBudget] reducer",
      false, "", "name");
  TCLAP::ValueArg<std::string> reducers(
      "", "reducers",
      "comma-separated reducers to compare (default: every one but none: " +
          reducers::builtinReducers().joinedNames(", ") + ")",
      false, "", "a,b,c");
  TCLAP::ValueArg<std::string> seeds(
      "", "seeds",
      "runs every reducer once a [LandmarkBudget] seed: A:B (A to B), or A,B,C; the table gives "
      "each run and the mean and std over the seeds",
      false, "", "A:B");
  TCLAP::ValueArg<std::string> max_steps(
      "", "max-steps",
      "stop after N steps of the rawlog (0: all); overrides [MappingApplication] max_steps", false,
      "", "N", cmd);
  TCLAP::ValueArg<unsigned> threads(
      "", "threads", "runs at once (default: one a core, at most one a run)", false, 0, "N");
  TCLAP::ValueArg<std::string> relocalize(
      "", "relocalize",
      "comma-separated rawlogs: every run's final map localizes each one (budget-slam localize)",
      false, "", "a.rawlog,b.rawlog");
  TCLAP::ValueArg<std::string> reference_trajectory(
      "", "reference-trajectory",
      "with --relocalize: trajectory.tum to measure traversals without ground truth against", false,
      "", "file.tum");
  TCLAP::ValueArg<std::string> resume(
      "", "resume",
      "continue the SLAM session that RUN_DIR ended (its session_state.txt): map, budget, "
      "reducer memory, robot pose; step indices run on",
      false, "", "RUN_DIR");
  TCLAP::ValueArg<std::string> skip_steps(
      "", "skip-steps", "leave the rawlog's first N steps unread (a rawlog split at step N)", false,
      "", "N");
  TCLAP::SwitchArg wake_up(
      "", "wake-up",
      "with --resume: find the robot on the saved map from the first steps' readings ([WakeUp]) "
      "instead of continuing where the last session stopped");
  TCLAP::SwitchArg offline_optimum(
      "", "offline-optimum",
      "adds the best place coverage any cap-sized map could give with hindsight (GLPK)");
  if (compare)
    cmd.add(reducers), cmd.add(seeds), cmd.add(threads), cmd.add(relocalize),
        cmd.add(reference_trajectory), cmd.add(offline_optimum);
  else
    cmd.add(reducer), cmd.add(resume), cmd.add(skip_steps), cmd.add(wake_up);
  TCLAP::ValueArg<std::string> cap("", "cap",
                                   "landmark cap, or none for no cap (reducer none, mi in "
                                   "objective or incremental mode); overrides [LandmarkBudget] "
                                   "max_landmarks",
                                   false, "", "N|none", cmd);
  TCLAP::ValueArg<std::string> backend(
      "", "backend",
      runs::builtinBackends().joinedNames(" or ") + "; overrides [MappingApplication] backend",
      false, "", runs::builtinBackends().joinedNames("|"), cmd);
  TCLAP::MultiArg<std::string> sets("", "set", "overrides any ini key", false, "Section.key=value",
                                    cmd);
  TCLAP::SwitchArg quiet("", "quiet", "no progress bar and no summary on stdout", cmd);
  TCLAP::SwitchArg force("", "force", "write into a non-empty output folder (deletes nothing)",
                         cmd);
  // Taken out of the command line by main() when the executable embeds Python
  // (python/src/PluginHost.cpp); here only for --help and for a build without Python.
  TCLAP::MultiArg<std::string> plugin(
      "", "plugin", "a Python file registering reducers (docs/PYTHON.md); repeatable", false,
      "FILE.py", cmd);

  std::vector<std::string> argv;
  argv.push_back("budget-slam " + args[1]);  // the usage names the program, not its path
  argv.insert(argv.end(), args.begin() + 2, args.end());
  try {
    cmd.parse(argv);
  } catch (const TCLAP::ArgException& e) {
    // The flag of the other command: say which one this command takes.
    const std::string id = e.argId();
    if (compare && id.find("--reducer") != std::string::npos &&
        id.find("--reducers") == std::string::npos)
      throw UsageError(
          "--reducer: compare runs the reducers of --reducers a,b,c (default: every one); see "
          "budget-slam compare --help");
    if (!compare && id.find("--reducers") != std::string::npos)
      throw UsageError(
          "--reducers: run takes one --reducer NAME (budget-slam compare runs several); see "
          "budget-slam run --help");
    throw UsageError(describe(e) + "; see budget-slam " + command + " --help");
  } catch (const TCLAP::ExitException&) {
    help_ = usage.text;  // --help or --version
    return;
  }

  if (plugin.isSet())
    throw UsageError(
        "--plugin: this budget-slam was built without Python (needs python3-dev and "
        "pybind11-dev); see docs/PYTHON.md");
  runs::RequestCommon common;
  common.config = config.getValue();
  common.rawlog = rawlog.getValue();
  common.outdir = outdir.getValue();
  common.sets = sets.getValue();
  common.quiet = quiet.getValue();
  common.force = force.getValue();
  runs::RunRequest run;
  runs::CompareRequest cmp;
  if (compare) {
    cmp.backend = backend.getValue();
    cmp.reducers = splitList(reducers.getValue()), cmp.threads = threads.getValue();
    cmp.relocalize = splitList(relocalize.getValue());
    cmp.reference_trajectory = reference_trajectory.getValue();
    cmp.offline_optimum = offline_optimum.getValue();
  } else {
    run.reducer = reducer.getValue(), run.backend = backend.getValue();
    run.resume = resume.getValue(), run.wake_up = wake_up.getValue();
    runs::checkWakeUp(run);
  }
  // Flag values are part of the command line: a bad one exits 2 before anything is written.
  try {
    refuseEmptyValues({&config, &rawlog, &outdir, &reducer, &reducers, &seeds, &max_steps, &cap,
                       &backend, &relocalize, &reference_trajectory, &resume, &skip_steps});
    if (max_steps.isSet()) common.max_steps = runs::parseMaxSteps(max_steps.getValue());
    if (skip_steps.isSet()) run.skip_steps = runs::parseSkipSteps(skip_steps.getValue());
    if (seeds.isSet()) cmp.seeds = runs::parseSeeds(seeds.getValue());
    std::optional<runs::Cap> cap_given;
    if (cap.isSet()) cap_given = runs::parseCap(cap.getValue());
    if (compare) {
      cmp.common = std::move(common), cmp.cap = cap_given;
      runs::checkRequest(cmp);
      request_ = std::move(cmp);
    } else {
      run.common = std::move(common), run.cap = cap_given;
      runs::checkRequest(run);
      request_ = std::move(run);
    }
  } catch (const ConfigError& e) {
    throw runs::withHelpHint(command, e);
  }
  loadConfigFile();
}

void BudgetSlamApp::loadConfigFile() {
  config_text_.reset();
  config_defaulted_ = false;
  const std::string& given = common().config;
  if (!given.empty() || params.getContent().empty()) {
    config_defaulted_ = given.empty();
    const std::string path = given.empty() ? "config.ini" : given;
    // Missing, a folder or over 1 MiB: the file cannot be read, a command-line error (exit 2).
    config_text_ = readIniFile(path, "config file '" + path + "'");
    config_label_ = path;
  }
}

void BudgetSlamApp::loadConfig() {
  if (!config_text_) return;
  params.clear();
  loadIniText(params, *config_text_, config_label_);
  config_text_.reset();
}

ProgressSettings BudgetSlamApp::progressSettings(const report::ReportOptions& report) const {
  ProgressSettings s;
  if (!common().quiet)
    s.style = err == &std::cerr && stderrIsTerminal() ? ProgressSettings::Style::Bar
                                                      : ProgressSettings::Style::Lines;
  s.line_every_s = report.progress_every_s;
  s.callback = on_progress;
  return s;
}

int BudgetSlamApp::run() {
  if (!out) out = &std::cout;
  if (!err) err = &std::cerr;
  if (!help_.empty()) {
    *out << help_ << std::flush;
    return runs::exitCode(stdoutWritten("") ? runs::RunStatus::Ok : runs::RunStatus::Failed);
  }
  // Without -c the settings come from the current folder's config.ini: never silently.
  if (config_defaulted_ && !common().quiet)
    *err << "budget-slam: note: no -c given: using ./config.ini" << std::endl;
  // Under main(), its guard has been there since start-up and a signal that came meanwhile still
  // counts; in a library (tests, Python), a stop request left by an earlier run does not.
  const bool first_guard = !StopSignals::installed();
  StopSignals signals;
  if (first_guard) Cancellation::clear();
  report::loadFigureFonts();  // while descriptors are to be had (report/Figure.h)
  try {
    if (const auto* r = std::get_if<runs::LocalizeRequest>(&request_)) return runLocalize(*r);
    if (const auto* r = std::get_if<runs::CompareRequest>(&request_)) return runCompare(*r);
    return runRun(std::get<runs::RunRequest>(request_));
  } catch (const std::exception& e) {
    // What the commands could not catch themselves (out of memory while reporting a failure).
    *err << "budget-slam: error: " << failureLine(e) << std::endl;
    return runs::exitCode(runs::RunStatus::Failed, runs::ErrorKind::Internal);
  }
}

const runs::RequestCommon& BudgetSlamApp::common() const {
  static const runs::RequestCommon none;
  return std::visit(
      [](const auto& r) -> const runs::RequestCommon& {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, std::monostate>)
          return none;
        else
          return r.common;
      },
      request_);
}

bool BudgetSlamApp::stdoutWritten(const std::string& outdir) {
  return flushStdout(*out, *err, "budget-slam",
                     outdir.empty() ? "" : "; the outputs are in " + outdir + "/");
}

runs::RequestContext BudgetSlamApp::requestContext() {
  runs::RequestContext context;
  context.params = params;
  context.config_text = std::move(config_text_);  // parsed by the command (its errors are its)
  config_text_.reset();
  context.config_label = config_label_;
  context.writer = std::string("budget-slam ") + kVersion;
  return context;
}

runs::RunHooks BudgetSlamApp::requestHooks() const {
  runs::RunHooks hooks;
  hooks.progress_out = err;
  hooks.progress = progressSettings(report::ReportOptions());  // lines: the ini's [Report]
  hooks.on_step = on_step;
  hooks.on_end_phase = on_end_phase;
  // Notes go to stderr unless --quiet (an error stays one line).
  hooks.note = [this](const std::string& line) {
    if (!common().quiet) *err << "budget-slam: note: " << line << std::endl;
  };
  hooks.warning = [this](const std::string& line) {
    *err << "budget-slam: warning: " << line << std::endl;
  };
  return hooks;
}

int BudgetSlamApp::runRun(const runs::RunRequest& request) {
  const runs::RunReport report = runs::run(request, requestContext(), requestHooks());
  const runs::RunOutcome& o = report.outcome;
  if (!o.ok()) {
    // The one error line of a run that did not end ok (nothing else on stderr says it).
    *err << "budget-slam: " << (o.status == runs::RunStatus::Interrupted ? "" : "error: ")
         << report.line << std::endl;
    return runs::exitCode(o);
  }
  if (!request.common.quiet) {
    const auto& pose = *report.final_pose;
    const auto& run = *o.run;
    *out << "budget-slam run: " << report.steps << " steps, backend " << run.backend << ", reducer "
         << run.reducer;
    if (run.cap) *out << ", cap " << *run.cap;
    *out << ": " << report.landmarks << " landmarks kept, " << run.counts.evictions << " dropped";
    if (run.counts.refused) *out << ", " << run.counts.refused << " newcomers refused";
    *out << "\n"
         << "final pose x=" << fixed(pose.x, 3) << " m y=" << fixed(pose.y, 3)
         << " m yaw=" << fixed(pose.phi * 180 / M_PI, 2) << " deg";
    if (o.ground_truth) {
      const auto val = [](double v, int d) {
        return std::isfinite(v) ? fixed(v, d) : std::string("n/a");
      };
      const auto& gt = o.ground_truth->errors;
      *out << "\nvs ground truth: ATE " << val(gt.trajectory_rmse_aligned, 3) << " m aligned ("
           << val(gt.trajectory_rmse, 3) << " m in the start frame), RPE " << val(gt.rpe.rmse, 3)
           << " m per 10 m, landmark RMSE " << val(gt.landmark_rmse_aligned, 3)
           << " m aligned, mean NEES " << val(o.ground_truth->nees.mean, 2);
    }
    *out << "\noutputs in " << report.folder << "/ (" << fixed(run.timings.steps_s, 2)
         << " s of SLAM)\n";
  }
  return stdoutWritten(report.folder) ? runs::exitCode(runs::RunStatus::Ok)
                                      : runs::exitCode(runs::RunStatus::Failed);
}

}  // namespace budget_slam::app
