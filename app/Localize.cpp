// budget-slam localize: a traversal localized in a run's final map (docs/OUTPUTS.md).
#include <tclap/CmdLine.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "BudgetSlamApp.h"
#include "CommandLineFlags.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/report/RunFiles.h"
#include "budget_slam/runs/Localizer.h"
#include "budget_slam/runs/MapFolder.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/SummaryJson.h"
#include "budget_slam/wakeup/WakeUpRun.h"

namespace budget_slam::app {
namespace {

constexpr double kDeg = M_PI / 180;
/// A reference trajectory longer than this is not one of budget-slam's [poses].
constexpr std::size_t kMaxReferencePoses = 50'000'000;

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(digits);
  o << v;
  return o.str();
}

/// "x,y,yaw_deg" -> pose (yaw in radians): three finite numbers, x and y within
/// limits::kMaxCoordinate, yaw within limits::kMaxAngle. ConfigError naming the flag.
mrpt::math::TPose2D parseStartPose(const std::string& text) {
  const std::string what = "--start-pose '" + printable(text) + "'";
  std::stringstream ss(text);
  std::vector<double> v;
  for (std::string item; std::getline(ss, item, ',');) {
    char* end = nullptr;
    const double d = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(d))
      throw ConfigError(what + ": expected x,y,yaw (metres, metres, degrees)");
    v.push_back(d);
  }
  if (v.size() != 3 || text.empty() || text.back() == ',')
    throw ConfigError(what + ": expected x,y,yaw (metres, metres, degrees)");
  if (std::abs(v[0]) > limits::kMaxCoordinate || std::abs(v[1]) > limits::kMaxCoordinate)
    throw ConfigError(what + ": x and y must be within 1e6 m of the map's origin");
  if (std::abs(v[2] * kDeg) > limits::kMaxAngle)
    throw ConfigError(what + ": yaw must be within 720 degrees");
  return {v[0], v[1], v[2] * kDeg};
}

/// summary.json's wake_up block (docs/OUTPUTS.md "localize --wake-up"); the error against the
/// truth is added by the caller.
nlohmann::json wakeUpJson(const wakeup::WakeUpRun& w, const wakeup::WakeUpOptions& options,
                          bool asked) {
  const auto& r = w.result;
  nlohmann::json j = {{"requested", asked ? "--wake-up" : "no start pose"},
                      {"found", w.found()},
                      {"status", wakeup::statusName(r.status)},
                      {"reason", wakeup::reasonName(r.reason)},
                      {"why_not_found", w.whyNotFound(options)},
                      {"correspondence", r.by_ids ? "ids" : "search"},
                      {"max_steps", options.max_steps},
                      {"steps_used", w.steps_read},
                      {"time_ms", w.wall_ms},
                      {"readings", r.readings},
                      {"landmarks", r.landmarks},
                      {"inliers", r.inliers},
                      {"hypotheses", r.hypotheses},
                      {"runner_up_landmarks", r.runner_up},
                      {"score", r.score},
                      {"runner_up_score", r.runner_up_score},
                      {"step", nullptr},
                      {"pose", nullptr},
                      {"cov", nullptr},
                      {"error", nullptr}};
  if (w.found()) {
    j["step"] = r.step;
    j["pose"] = {{"x", r.pose.mean.x}, {"y", r.pose.mean.y}, {"yaw", r.pose.mean.phi}};
    nlohmann::json cov = nlohmann::json::array();
    for (int i = 0; i < 3; ++i)
      cov.push_back({r.pose.cov(i, 0), r.pose.cov(i, 1), r.pose.cov(i, 2)});
    j["cov"] = cov;
  }
  return j;
}

}  // namespace

void BudgetSlamApp::initializeLocalize(const std::vector<std::string>& args) {
  cli_ = runs::Request();
  help_.clear();
  cli_.command = "localize";
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
  cli_.config = config.getValue();
  cli_.map_dir = map.getValue();
  cli_.rawlog = rawlog.getValue();
  cli_.outdir = outdir.getValue();
  // Given empty, it is still given: refused below, never taken as "derive it".
  if (start.isSet()) cli_.start_pose = start.getValue();
  cli_.reference_trajectory = reference.getValue();
  cli_.wake_up = wake_up.getValue();
  cli_.sets = sets.getValue();
  cli_.quiet = quiet.getValue();
  cli_.force = force.getValue();
  // a bad start pose is part of the command line: exit 2 before anything is written
  try {
    if (cli_.start_pose) parseStartPose(*cli_.start_pose);
    if (cli_.start_pose && cli_.wake_up)
      throw ConfigError("--wake-up: not with --start-pose (a start pose is not looked for)");
    refuseEmptyValues({&config, &map, &rawlog, &outdir, &reference, &max_steps});
    if (max_steps.isSet()) cli_.max_steps = parseMaxSteps(max_steps.getValue());
  } catch (const ConfigError& e) {
    throw UsageError(e.what() + std::string("; see budget-slam localize --help"));
  }
  loadConfigFile();
}

int BudgetSlamApp::runLocalize() {
  std::optional<report::OutputFolder> folder;
  std::unique_ptr<runs::Localizer> localizer;
  nlohmann::json wake_json;  ///< summary.json's wake_up block, when the robot woke up
  // One line, which also says why summary.json could not be written when it could not.
  const auto fail = [&](const std::string& why, runs::RunStatus status, runs::ErrorKind kind) {
    const std::string msg = printable(why);
    std::string not_saved;
    try {
      // Before the first step nothing is worth keeping: the next command replaces it.
      const bool started = localizer && localizer->stepsDone() > 0;
      if (localizer) {
        nlohmann::json given = {{"map", cli_.map_dir}, {"started", started}};
        if (!wake_json.is_null()) given["wake_up"] = wake_json;
        localizer->finish(status, kind, msg, given);
        not_saved = localizer->summaryError();
      } else if (folder) {
        runs::RunOutcome o;
        o.fail(status, kind, msg);
        o.given = {{"command", "localize"}, {"started", false}};
        runs::writeSummary(folder->file("summary.json"), o);
      }
    } catch (const std::exception& e) {
      not_saved = failureLine(e);
    }
    *err << "budget-slam: " << (status == runs::RunStatus::Interrupted ? "" : "error: ")
         << withAlso(msg, not_saved) << std::endl;
    return runs::exitCode(status, kind);
  };
  const auto interrupted = [&](const std::string& why) {
    return fail(why, runs::RunStatus::Interrupted, runs::ErrorKind::Stopped);
  };
  const auto failed = [&](const std::exception& e, const std::string& why) {
    return fail(why, runs::RunStatus::Failed, runs::errorKindOf(e));
  };

  runs::RunConfig rc;
  try {
    loadConfig();
    rc = runs::loadRunConfig(params, cli_, config_label_);
    for (const auto& w : rc.warnings) *err << "budget-slam: warning: " << w << std::endl;
    folder.emplace(rc.outdir, cli_.force);
  } catch (const Error& e) {
    if (!cli_.outdir.empty() && !folder) try {
        folder.emplace(cli_.outdir, cli_.force);
      } catch (const Error&) {
      }
    return failed(e, e.what());
  }

  try {
    Cancellation::check();  // a stop request that came while the program started
    writeFileAtomically(folder->file("config_used.ini"), rc.ini.getContent());
    metrics::MetricsOptions metric_options;
    metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
    const runs::MapFolder map =
        runs::loadMapFolder(cli_.map_dir, rc.localization.max_map_landmarks);
    std::vector<TrajectoryPoint> reference;
    if (!cli_.reference_trajectory.empty())
      reference = report::readTrajectoryTum(cli_.reference_trajectory, kMaxReferencePoses);
    const auto truth = dataset::loadGroundTruth(rc.rawlog, rc.mapping.ground_truth_file,
                                                rc.mapping.ground_truth_file_robot);

    // The traversal is read whole first: the ground-truth row of a step depends on the count.
    std::vector<Step> steps;
    dataset::RawlogReader reader(rc.rawlog);
    // A signal ends the reading within one read of the file, even inside a large object.
    reader.setStopCheck([] { return Cancellation::requested(); });
    ProgressReporter reading(*err, "reading the rawlog", progressSettings(rc.report));
    for (;;) {
      auto s = reader.next();
      if (s) {
        steps.push_back(std::move(*s));
        reading.update(reader.progress(), steps.size(), 0, "");
      }
      if (Cancellation::requested()) {
        reading.finish(false);
        return interrupted(std::string("interrupted by ") + Cancellation::signalName() +
                           " while reading the rawlog");
      }
      if (!s) break;
    }
    reading.finish(true);
    if (reader.bearingRangeSteps() == 0)
      throw InputError("rawlog '" + rc.rawlog + "' holds no CObservationBearingRange");
    const std::size_t in_rawlog = steps.size();
    if (rc.localization.max_steps && steps.size() > rc.localization.max_steps)
      steps.resize(rc.localization.max_steps);

    std::optional<mrpt::math::TPose2D> given;
    if (cli_.start_pose) given = parseStartPose(*cli_.start_pose);
    // No start pose anywhere (no --start-pose, no ground truth in the map's frame, no reference):
    // wake up on the map rather than fail (docs/OUTPUTS.md "localize --wake-up").
    const bool start_known = given || (!truth.path.empty() && map.alignment) || !reference.empty();
    std::optional<wakeup::WakeUpRun> woke;
    if (cli_.wake_up || !start_known) {
      if (!cli_.wake_up && !cli_.quiet)
        *err << "budget-slam: no start pose (no --start-pose, no ground truth in the map's frame, "
                "no --reference-trajectory): waking up on the map"
             << std::endl;
      wakeup::WakeUpOptions wake_options;
      wake_options.loadFromConfigFile(rc.ini, wakeup::WakeUpOptions::kSection);
      std::size_t next = 0;
      woke = wakeup::wakeUpOver(
          map.landmarks,
          [&]() -> const Step* { return next < steps.size() ? &steps[next++] : nullptr; },
          wake_options, wakeup::readingNoiseOf(rc.ini));
      wake_json = wakeUpJson(*woke, wake_options, cli_.wake_up);
      if (!woke->found()) {
        const std::string why = woke->whyNotFound(wake_options) + "; no pose is guessed";
        runs::RunOutcome o;
        o.fail(runs::RunStatus::NotFound, runs::ErrorKind::None, why);
        o.given = {{"command", "localize"},
                   {"rawlog", rc.rawlog},
                   {"map", cli_.map_dir},
                   {"started", false},
                   {"wake_up", wake_json}};
        std::string not_saved;
        try {
          runs::writeSummary(folder->file("summary.json"), o);
        } catch (const std::exception& e) {
          not_saved = failureLine(e);
          o.fail(runs::RunStatus::Failed, runs::ErrorKind::Output, why);
        }
        *err << "budget-slam: error: wake-up: " << withAlso(why, not_saved) << std::endl;
        return runs::exitCode(o);
      }
      given = woke->result.pose.mean;
    }
    auto inputs =
        runs::resolveLocalization(steps, in_rawlog, truth, map.alignment, given,
                                  cli_.reference_trajectory.empty() ? nullptr : &reference,
                                  cli_.reference_trajectory, rc.localization);
    if (woke) {
      // The steps that woke the robot up are not localized: the filter starts at the pose found,
      // at the last of them, with its covariance.
      const std::size_t used = woke->steps_read;
      const auto& at = inputs.truth.poses[used - 1];
      if (at) {
        const auto e = wakeup::wakeUpError(woke->result.pose, *at);
        wake_json["error"] = {{"against", inputs.truth.kind},
                              {"xy_m", e.xy_m},
                              {"yaw_deg", e.yaw_deg},
                              {"within_success", e.xy_m <= rc.localization.success_xy &&
                                                     e.yaw_deg <= rc.localization.success_yaw_deg}};
      }
      inputs.start = woke->result.pose;
      inputs.start_source = "wake-up";
      steps.erase(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(used));
      inputs.truth.poses.erase(inputs.truth.poses.begin(),
                               inputs.truth.poses.begin() + static_cast<std::ptrdiff_t>(used));
    }
    // A path of one pose is a run without history (keep_history = false): no area to score in.
    if (map.path.size() >= 2) inputs.mapping_path = map.path;
    localizer = std::make_unique<runs::Localizer>(rc.ini, rc.localization,
                                                  metric_options.reloc_min_landmarks, *folder,
                                                  map.landmarks, inputs);
    ProgressReporter progress(*err, "localize", progressSettings(rc.report));
    for (const auto& s : steps) {
      localizer->process(s);
      progress.update(static_cast<double>(localizer->stepsDone()) / steps.size(),
                      localizer->stepsDone(), steps.size(), "");
      if (on_step) on_step(s.index);
      if (Cancellation::requested()) {
        progress.finish(false);
        return interrupted(std::string("interrupted by ") + Cancellation::signalName() +
                           " after step " + std::to_string(s.index));
      }
    }
    progress.finish(true);
    // A map of another place (whose sensor IDs may happen to repeat): readings pair with its
    // landmarks but do not agree with where it has them. Every step is then dead reckoning. (No
    // step left after the wake-up: nothing to say.)
    const std::size_t paired = localizer->readingsPairedWithMap(),
                      agree = localizer->readingsConsistentWithMap();
    if (localizer->stepsDone() > 0 && (2 * agree < paired || paired == 0))
      *err << "budget-slam: warning: " << agree << " of the " << paired << " readings of "
           << rc.rawlog << " that pair with a landmark of the map in " << cli_.map_dir
           << " agree with it (innovation within the 99.9% bound): the map and the traversal "
              "share no place"
           << std::endl;
    nlohmann::json summary_given = {{"rawlog", rc.rawlog},      {"sidecar_ini", rc.sidecar},
                                    {"config", config_label_},  {"map", cli_.map_dir},
                                    {"map_status", map.status}, {"started", true}};
    if (!wake_json.is_null()) summary_given["wake_up"] = wake_json;
    const runs::RunOutcome summary =
        localizer->finish(runs::RunStatus::Ok, runs::ErrorKind::None, "", summary_given);
    if (!localizer->writeError().empty()) {
      // An output that could not be written (a full disk): summary.json says which, if it could.
      *err << "budget-slam: error: " << withAlso(localizer->writeError(), localizer->summaryError())
           << std::endl;
      return runs::exitCode(runs::RunStatus::Failed, runs::ErrorKind::Output);
    }
    if (!cli_.quiet) {
      const auto sc = localizer->score();
      *out << "budget-slam localize: " << sc.steps << " steps in a map of " << map.landmarks.size()
           << " landmarks, start from " << inputs.start_source << "\n";
      if (woke)
        *out << "woken up at step " << woke->result.step << " after " << woke->steps_read
             << " step(s) (" << (woke->result.by_ids ? "by landmark ids" : "by search") << ", "
             << fixed(woke->wall_ms, 1) << " ms)"
             << (wake_json.contains("error")
                     ? ", " + fixed(wake_json["error"]["xy_m"].get<double>(), 3) + " m and " +
                           fixed(wake_json["error"]["yaw_deg"].get<double>(), 2) +
                           " deg from the truth"
                     : std::string())
             << "\n";
      if (!inputs.truth.kind.empty())
        *out << "against the "
             << (inputs.truth.kind == "ground_truth" ? "ground truth" : "reference trajectory")
             << ": RMSE " << fixed(sc.rmse_m, 3) << " m, max " << fixed(sc.max_m, 3) << " m, lost "
             << fixed(sc.lost_pct, 1) << "% of the steps (error above "
             << fixed(rc.localization.lost_threshold, 2) << " m), NEES " << fixed(sc.nees_mean, 2)
             << "\n";
      *out << "at least " << metric_options.reloc_min_landmarks << " map landmarks observed at "
           << fixed(sc.coverage_pct, 1) << "% of the steps (mean " << fixed(sc.mean_landmarks, 2)
           << ")\n";
      if (summary.given["localization"]["diverged_at_step"].is_number())
        *out << "the filter was lost for good at step "
             << summary.given["localization"]["diverged_at_step"] << "\n";
      *out << "outputs in " << folder->path() << "/\n";
    }
    return runs::exitCode(stdoutWritten(folder->path()) ? runs::RunStatus::Ok
                                                        : runs::RunStatus::Failed);
  } catch (const Interrupted&) {
    return interrupted(std::string("interrupted by ") + Cancellation::signalName() +
                       " before the first step");
  } catch (const std::exception& e) {
    return failed(e, failureLine(e));
  }
}

}  // namespace budget_slam::app
