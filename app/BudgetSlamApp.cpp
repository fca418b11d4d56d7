#include "BudgetSlamApp.h"

#include <tclap/CmdLine.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "Interrupt.h"
#include "Pipeline.h"
#include "ProgressBar.h"
#include "RunConfig.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/report/RunFiles.h"

namespace budget_slam::app {
namespace {

constexpr const char* kUsage =
    "usage: budget-slam run|compare -c config.ini [-i in.rawlog] [-o outdir] [options]\n"
    "       budget-slam <command> --help";

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string joined(const std::set<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
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
  if (args.size() < 2 || (args[1] != "run" && args[1] != "compare")) {
    if (args.size() >= 2 && (args[1] == "--help" || args[1] == "-h")) throw ConfigError(kUsage);
    throw ConfigError(std::string("expected a command, run or compare\n") + kUsage);
  }
  cli_ = CommandLine();
  cli_.command = args[1];
  const bool compare = cli_.command == "compare";

  TCLAP::CmdLine cmd(compare ? "Runs every reducer and the unreduced reference on one rawlog and "
                               "compares them"
                             : "Runs landmark SLAM on a rawlog under a landmark budget",
                     ' ', "0.1", true);
  cmd.setExceptionHandling(false);
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
  TCLAP::ValueArg<std::string> reducer("", "reducer", "reducer; overrides [LandmarkBudget] reducer",
                                       false, "", "name", cmd);
  TCLAP::ValueArg<std::string> reducers("", "reducers", "comma-separated reducers to compare",
                                        false, "", "a,b,c");
  TCLAP::ValueArg<unsigned> threads(
      "", "threads", "runs at once (default: one a core, at most one a run)", false, 0, "N");
  TCLAP::SwitchArg offline_optimum(
      "", "offline-optimum",
      "adds the best place coverage any cap-sized map could give with hindsight (GLPK)");
  if (compare) cmd.add(reducers), cmd.add(threads), cmd.add(offline_optimum);
  TCLAP::ValueArg<long long> cap("", "cap",
                                 "landmark cap; overrides [LandmarkBudget] "
                                 "max_landmarks",
                                 false, 0, "N", cmd);
  TCLAP::ValueArg<std::string> backend("", "backend",
                                       "ekf or graph; overrides "
                                       "[MappingApplication] backend",
                                       false, "", "ekf|graph", cmd);
  TCLAP::MultiArg<std::string> sets("", "set", "overrides any ini key", false, "Section.key=value",
                                    cmd);
  TCLAP::SwitchArg quiet("", "quiet", "no progress bar and no summary on stdout", cmd);
  TCLAP::SwitchArg force("", "force", "write into a non-empty output folder (deletes nothing)",
                         cmd);

  std::vector<std::string> argv;
  argv.push_back(args[0] + " " + args[1]);
  argv.insert(argv.end(), args.begin() + 2, args.end());
  try {
    cmd.parse(argv);
  } catch (const TCLAP::ArgException& e) {
    throw ConfigError(
        "command line: " + e.error() +
        (e.argId().empty() || e.argId() == " " ? std::string() : " (" + e.argId() + ")"));
  } catch (const TCLAP::ExitException&) {
    throw ConfigError(kUsage);
  }

  cli_.config = config.getValue();
  cli_.rawlog = rawlog.getValue();
  cli_.outdir = outdir.getValue();
  cli_.reducer = reducer.getValue();
  cli_.backend = backend.getValue();
  if (cap.isSet()) cli_.cap = cap.getValue();
  cli_.sets = sets.getValue();
  if (compare) cli_.reducers = splitList(reducers.getValue()), cli_.threads = threads.getValue();
  if (compare) cli_.offline_optimum = offline_optimum.getValue();
  cli_.quiet = quiet.getValue();
  cli_.force = force.getValue();

  if (!cli_.config.empty() || params.getContent().empty()) {
    const std::string path = cli_.config.empty() ? "config.ini" : cli_.config;
    std::ifstream in(path);
    if (!in) throw ConfigError("config file '" + path + "': no such file or not readable");
    std::stringstream ss;
    ss << in.rdbuf();
    params.setContent(ss.str());
    config_label_ = path;
  }
}

int BudgetSlamApp::run() {
  if (!out) out = &std::cout;
  if (!err) err = &std::cerr;
  InterruptGuard guard;
  InterruptGuard::clear();
  return cli_.command == "compare" ? runCompare() : runRun();
}

int BudgetSlamApp::runRun() {
  std::optional<report::OutputFolder> folder;
  std::unique_ptr<Pipeline> pipeline;
  std::size_t steps_read = 0;

  const auto fail = [&](const std::string& msg, const std::string& status) {
    *err << "budget-slam: " << (status == "interrupted" ? "" : "error: ") << msg << std::endl;
    try {
      if (pipeline) {
        pipeline->finish(status, msg, steps_read);
      } else if (folder) {
        report::writeJson(folder->file("summary.json"), {{"status", status}, {"error", msg}});
      }
    } catch (const std::exception& e) {
      *err << "budget-slam: error: while saving outputs: " << e.what() << std::endl;
    }
    return status == "interrupted" ? 130 : 1;
  };

  RunConfig rc;
  try {
    rc = loadRunConfig(params, cli_, config_label_);
  } catch (const Error& e) {
    if (!cli_.outdir.empty()) {
      try {
        folder.emplace(cli_.outdir, cli_.force);
      } catch (const Error&) {
      }
    }
    return fail(e.what(), "failed");
  }

  try {
    folder.emplace(rc.outdir, cli_.force);
  } catch (const Error& e) {
    return fail(e.what(), "failed");
  }

  try {
    std::ofstream(folder->file("config_used.ini")) << rc.ini.getContent();
    auto truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(
        rc.rawlog, rc.mapping.ground_truth_file, rc.mapping.ground_truth_file_robot));
    pipeline = std::make_unique<Pipeline>(rc.ini, rc.mapping.backend, rc.budget, *folder, truth,
                                          rc.mapping.keep_history);

    dataset::RawlogReader reader(rc.rawlog);
    ProgressBar bar(*err, !cli_.quiet && err == &std::cerr && stderrIsTerminal());
    const std::size_t limit = rc.mapping.max_steps;
    while (limit == 0 || steps_read < limit) {
      auto step = reader.next();
      if (!step) break;
      steps_read = reader.stepsRead();
      pipeline->process(*step);
      bar.update(reader.progress(), "step " + std::to_string(step->index) + ", " +
                                        std::to_string(pipeline->backend().landmarkCount()) +
                                        " landmarks");
      if (on_step) on_step(step->index);
      if (InterruptGuard::requested()) {
        bar.done();
        return fail(std::string("interrupted by ") + InterruptGuard::what() + " after step " +
                        std::to_string(step->index),
                    "interrupted");
      }
    }
    bar.done();
    if (reader.bearingRangeSteps() == 0)
      throw InputError("rawlog '" + rc.rawlog + "' holds no CObservationBearingRange (it holds: " +
                       joined(reader.observationClasses()) + ")");

    const auto summary = pipeline->finish(
        "ok", "", steps_read,
        {{"rawlog", rc.rawlog}, {"sidecar_ini", rc.sidecar}, {"config", config_label_}});
    if (!cli_.quiet) {
      const auto pose = pipeline->backend().robotPose().mean;
      *out << "budget-slam run: " << steps_read << " steps, backend " << rc.mapping.backend
           << ", reducer " << rc.budget.reducer;
      if (pipeline->budget().capped()) *out << ", cap " << rc.budget.max_landmarks;
      *out << ": " << pipeline->backend().landmarkCount() << " landmarks kept, "
           << pipeline->evictions() << " dropped\n"
           << "final pose x=" << fixed(pose.x, 3) << " m y=" << fixed(pose.y, 3)
           << " m yaw=" << fixed(pose.phi * 180 / M_PI, 2) << " deg";
      if (summary.contains("ground_truth")) {
        const auto& g = summary["ground_truth"];
        const auto val = [](const nlohmann::json& v, int d) {
          return v.is_number() ? fixed(v.get<double>(), d) : std::string("n/a");
        };
        *out << "; vs ground truth: trajectory RMSE " << val(g["trajectory_rmse_m"], 3)
             << " m, landmark RMSE " << val(g["landmark_rmse_m"], 3) << " m, mean NEES "
             << val(g["nees_mean"], 2);
      }
      *out << "\noutputs in " << folder->path() << "/ (" << fixed(pipeline->totalStepSeconds(), 2)
           << " s of SLAM)\n";
    }
    return 0;
  } catch (const Error& e) {
    return fail(e.what(), "failed");
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what(), "failed");
  }
}

}  // namespace budget_slam::app
