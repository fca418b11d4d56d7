// runs::localize: one `budget-slam localize` from its typed specification (docs/OUTPUTS.md
// "budget-slam localize").
#include <cmath>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/runs/Localize.h"
#include "budget_slam/runs/Localizer.h"
#include "budget_slam/runs/MapFolder.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/SummaryJson.h"
#include "budget_slam/wakeup/WakeUpRun.h"

namespace budget_slam::runs {
namespace {

constexpr double kDeg = M_PI / 180;
/// A reference trajectory longer than this is not one of budget-slam's [poses].
constexpr std::size_t kMaxReferencePoses = 50'000'000;

/// The wake-up's block, as far as the wake-up itself knows it (the error against the truth is
/// added once the truth is resolved).
LocalizationWakeUp wakeUpBlock(const wakeup::WakeUpRun& w, const wakeup::WakeUpOptions& options,
                               bool asked) {
  LocalizationWakeUp b;
  b.asked = asked;
  b.result = w.result;
  b.why_not_found = w.whyNotFound(options);
  b.max_steps = options.max_steps;
  b.steps_used = w.steps_read;
  b.time_ms = w.wall_ms;
  return b;
}

}  // namespace

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

void checkLocalizeRequest(const Request& request) {
  if (request.start_pose) parseStartPose(*request.start_pose);
  if (request.start_pose && request.wake_up)
    throw ConfigError("--wake-up: not with --start-pose (a start pose is not looked for)");
}

LocalizeReport localize(const Request& request, RequestContext context, const RunHooks& hooks) {
  const Request& cli = request;
  LocalizeReport report;
  std::optional<report::OutputFolder> folder;
  std::unique_ptr<Localizer> localizer;
  std::optional<LocalizationWakeUp> wake;  ///< summary.json's wake_up block, once looked for
  std::ostringstream no_progress;
  std::ostream& progress_out = hooks.progress_out ? *hooks.progress_out : no_progress;

  // Ends the localization as `status`: summary.json (through the localizer when there is one)
  // and the one line, which also says why summary.json could not be written when it could not.
  const auto fail = [&](const std::string& why, RunStatus status, ErrorKind kind) {
    const std::string msg = printable(why);
    std::string not_saved;
    try {
      // Before the first step nothing is worth keeping: the next command replaces it.
      const bool started = localizer && localizer->stepsDone() > 0;
      if (localizer) {
        report.outcome = localizer->finish(status, kind, msg,
                                           {{"map", cli.map_dir}, {"started", started}}, wake);
        not_saved = localizer->summaryError();
      } else if (folder) {
        report.outcome.fail(status, kind, msg);
        report.outcome.given = {{"command", "localize"}, {"started", false}};
        writeSummary(folder->file("summary.json"), report.outcome);
      }
    } catch (const std::exception& e) {
      not_saved = failureLine(e);
    }
    // The outcome is the one asked for, whatever the localizer made of it.
    report.outcome.status = status, report.outcome.kind = kind, report.outcome.error = msg;
    report.line = withAlso(msg, not_saved);
    return report;
  };
  const auto interrupted = [&](const std::string& why) {
    return fail(why, RunStatus::Interrupted, ErrorKind::Stopped);
  };
  const auto failed = [&](const std::exception& e, const std::string& why) {
    return fail(why, RunStatus::Failed, errorKindOf(e));
  };
  const auto warn = [&](const std::string& line) {
    report.warnings.push_back(line);
    if (hooks.warning) hooks.warning(line);
  };

  RunConfig rc;
  try {
    rc = loadRunConfig(request, context);
    for (const auto& w : rc.warnings) warn(w);
    folder.emplace(rc.outdir, cli.force);
  } catch (const Error& e) {
    if (!cli.outdir.empty() && !folder) try {
        folder.emplace(cli.outdir, cli.force);
      } catch (const Error&) {
      }
    if (folder) report.folder = folder->path();
    return failed(e, e.what());
  } catch (const std::exception& e) {
    // Not one of budget-slam's errors (MRPT's own): one line, nothing written.
    report.outcome.fail(RunStatus::Failed, ErrorKind::Internal, failureLine(e));
    report.line = report.outcome.error;
    return report;
  }
  report.folder = folder->path();
  ProgressSettings progress_settings = hooks.progress;
  progress_settings.line_every_s = rc.report.progress_every_s;  // the merged ini's [Report]

  try {
    Cancellation::check();  // a stop request that came while the program started
    writeFileAtomically(folder->file("config_used.ini"), configUsed(rc.ini));
    metrics::MetricsOptions metric_options;
    metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
    const MapFolder map = loadMapFolder(cli.map_dir, rc.localization.max_map_landmarks);
    report.map_landmarks = map.landmarks.size();
    std::vector<TrajectoryPoint> reference;
    if (!cli.reference_trajectory.empty())
      reference = report::readTrajectoryTum(cli.reference_trajectory, kMaxReferencePoses);
    const auto truth = dataset::loadGroundTruth(rc.rawlog, rc.mapping.ground_truth_file,
                                                rc.mapping.ground_truth_file_robot);

    // The traversal is read whole first: the ground-truth row of a step depends on the count.
    std::vector<Step> steps;
    dataset::RawlogReader reader(rc.rawlog);
    // A signal ends the reading within one read of the file, even inside a large object.
    reader.setStopCheck([] { return Cancellation::requested(); });
    ProgressReporter reading(progress_out, "reading the rawlog", progress_settings);
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
    if (cli.start_pose) given = parseStartPose(*cli.start_pose);
    // No start pose anywhere (no --start-pose, no ground truth in the map's frame, no reference):
    // wake up on the map rather than fail (docs/OUTPUTS.md "localize --wake-up").
    const bool start_known = given || (!truth.path.empty() && map.alignment) || !reference.empty();
    std::optional<wakeup::WakeUpRun> woke;
    if (cli.wake_up || !start_known) {
      if (!cli.wake_up && hooks.note)
        hooks.note(
            "no start pose (no --start-pose, no ground truth in the map's frame, no "
            "--reference-trajectory): waking up on the map");
      wakeup::WakeUpOptions wake_options;
      wake_options.loadFromConfigFile(rc.ini, wakeup::WakeUpOptions::kSection);
      std::size_t next = 0;
      woke = wakeup::wakeUpOver(
          map.landmarks,
          [&]() -> const Step* { return next < steps.size() ? &steps[next++] : nullptr; },
          wake_options, wakeup::readingNoiseOf(rc.ini));
      wake = wakeUpBlock(*woke, wake_options, cli.wake_up);
      if (!woke->found()) {
        const std::string why = woke->whyNotFound(wake_options) + "; no pose is guessed";
        RunOutcome& o = report.outcome;
        o.fail(RunStatus::NotFound, ErrorKind::None, why);
        o.wake_up = wake;
        o.given = {{"command", "localize"},
                   {"rawlog", rc.rawlog},
                   {"map", cli.map_dir},
                   {"started", false}};
        std::string not_saved;
        try {
          writeSummary(folder->file("summary.json"), o);
        } catch (const std::exception& e) {
          not_saved = failureLine(e);
          o.fail(RunStatus::Failed, ErrorKind::Output, why);
        }
        report.line = "wake-up: " + withAlso(why, not_saved);
        return report;
      }
      given = woke->result.pose.mean;
    }
    auto inputs = resolveLocalization(steps, in_rawlog, truth, map.alignment, given,
                                      cli.reference_trajectory.empty() ? nullptr : &reference,
                                      cli.reference_trajectory, rc.localization);
    if (woke) {
      // The steps that woke the robot up are not localized: the filter starts at the pose found,
      // at the last of them, with its covariance.
      const std::size_t used = woke->steps_read;
      const auto& at = inputs.truth.poses[used - 1];
      if (at) {
        const auto e = wakeup::wakeUpError(woke->result.pose, *at);
        wake->error = LocalizationWakeUp::Error{
            inputs.truth.kind, e.xy_m, e.yaw_deg,
            e.xy_m <= rc.localization.success_xy && e.yaw_deg <= rc.localization.success_yaw_deg};
      }
      inputs.start = woke->result.pose;
      inputs.start_source = "wake-up";
      steps.erase(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(used));
      inputs.truth.poses.erase(inputs.truth.poses.begin(),
                               inputs.truth.poses.begin() + static_cast<std::ptrdiff_t>(used));
    }
    // A path of one pose is a run without history (keep_history = false): no area to score in.
    if (map.path.size() >= 2) inputs.mapping_path = map.path;
    localizer =
        std::make_unique<Localizer>(rc.ini, rc.localization, metric_options.reloc_min_landmarks,
                                    *folder, map.landmarks, inputs);
    ProgressReporter progress(progress_out, "localize", progress_settings);
    for (const auto& s : steps) {
      localizer->process(s);
      progress.update(static_cast<double>(localizer->stepsDone()) / steps.size(),
                      localizer->stepsDone(), steps.size(), "");
      if (hooks.on_step) hooks.on_step(s.index);
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
      warn(std::to_string(agree) + " of the " + std::to_string(paired) + " readings of " +
           rc.rawlog + " that pair with a landmark of the map in " + cli.map_dir +
           " agree with it (innovation within the 99.9% bound): the map and "
           "the traversal share no place");
    const nlohmann::json summary_given = {
        {"rawlog", rc.rawlog}, {"sidecar_ini", rc.sidecar}, {"config", context.config_label},
        {"map", cli.map_dir},  {"map_status", map.status},  {"started", true}};
    report.outcome = localizer->finish(RunStatus::Ok, ErrorKind::None, "", summary_given, wake);
    // An output that could not be written (a full disk): summary.json says which, if it could.
    if (!localizer->writeError().empty())
      report.line = withAlso(localizer->writeError(), localizer->summaryError());
    return report;
  } catch (const Interrupted&) {
    return interrupted(std::string("interrupted by ") + Cancellation::signalName() +
                       " before the first step");
  } catch (const std::exception& e) {
    return failed(e, failureLine(e));
  }
}

}  // namespace budget_slam::runs
