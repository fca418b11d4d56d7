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
#include "budget_slam/engine/RawlogSteps.h"
#include "budget_slam/engine/RunLife.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/localization/Localizer.h"
#include "budget_slam/localization/MapFolder.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/runs/Localize.h"
#include "budget_slam/runs/RunConfig.h"
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

Pose2 parseStartPose(const std::string& text) {
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

namespace {

/// What a localization reads before its filter starts.
struct LocalizeInputs {
  RunConfig rc;
  metrics::MetricsOptions metric_options;
  MapFolder map;
  std::vector<TrajectoryPoint> reference;  ///< --reference-trajectory
  dataset::GroundTruth truth;
  std::vector<Step> steps;  ///< the traversal, at most [Localization] max_steps
  std::size_t in_rawlog = 0;
  ProgressSettings progress;  ///< with the merged ini's interval
};

/// What every localization is given first (summary.json's command).
RunGiven localizeGiven() {
  RunGiven g;
  g.command = "localize";
  return g;
}

/// What a localization that localized its steps was given (summary.json).
RunGiven localizedGiven(const LocalizeInputs& in, const std::string& config_label,
                        const std::string& map_dir) {
  RunGiven g;
  g.rawlog = in.rc.rawlog, g.sidecar_ini = in.rc.sidecar, g.config = config_label;
  g.map = map_dir, g.map_status = in.map.status, g.started = true;
  return g;
}

/// The map folder, the reference trajectory, the ground truth and the traversal, read whole first
/// (the ground-truth row of a step depends on the count). False when a stop request came while
/// reading the rawlog.
bool readInputs(const LocalizeRequest& cli, std::ostream& progress_out, LocalizeInputs& in) {
  const RunConfig& rc = in.rc;
  in.metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
  in.map = loadMapFolder(cli.map_dir, rc.localization.max_map_landmarks);
  if (!cli.reference_trajectory.empty())
    in.reference = report::readTrajectoryTum(cli.reference_trajectory, kMaxReferencePoses);
  in.truth = dataset::loadGroundTruth(rc.rawlog, rc.mapping.ground_truth_file,
                                      rc.mapping.ground_truth_file_robot);
  ProgressReporter reading(progress_out, "reading the rawlog", in.progress);
  auto steps = readRawlogSteps(rc.rawlog, 0, &reading);
  if (!steps) return false;
  in.steps = std::move(*steps);
  in.in_rawlog = in.steps.size();
  if (rc.localization.max_steps && in.steps.size() > rc.localization.max_steps)
    in.steps.resize(rc.localization.max_steps);
  return true;
}

/// The start pose from the wake-up (the robot looked for on the map over the first steps), when
/// it is asked for or nothing else gives one; `wake` gets its block. Found or not, the wake-up's
/// run; nullopt when it was not needed.
std::optional<wakeup::WakeUpRun> wakeUpIfNeeded(const LocalizeRequest& cli, const RunHooks& hooks,
                                                const std::optional<Pose2>& given,
                                                const LocalizeInputs& in,
                                                std::optional<LocalizationWakeUp>& wake) {
  // No start pose anywhere (no --start-pose, no ground truth in the map's frame, no reference):
  // wake up on the map rather than fail (docs/OUTPUTS.md "localize --wake-up").
  const bool start_known =
      given || (!in.truth.path.empty() && in.map.alignment) || !in.reference.empty();
  if (!cli.wake_up && start_known) return std::nullopt;
  if (!cli.wake_up && hooks.note)
    hooks.note(
        "no start pose (no --start-pose, no ground truth in the map's frame, no "
        "--reference-trajectory): waking up on the map");
  wakeup::WakeUpOptions wake_options;
  wake_options.loadFromConfigFile(in.rc.ini, wakeup::WakeUpOptions::kSection);
  std::size_t next = 0;
  auto woke = wakeup::wakeUpOver(
      in.map.landmarks,
      [&]() -> const Step* { return next < in.steps.size() ? &in.steps[next++] : nullptr; },
      wake_options, wakeup::readingNoiseOf(in.rc.ini));
  wake = wakeUpBlock(woke, wake_options, cli.wake_up);
  return woke;
}

/// A robot the wake-up did not find: summary.json says not_found, and why; no pose is guessed.
LocalizeReport notFound(LocalizeReport report, const std::string& why, RunLife& life,
                        const std::optional<LocalizationWakeUp>& wake) {
  RunOutcome& o = report.outcome;
  o.fail(RunStatus::NotFound, ErrorKind::None, why);
  o.wake_up = wake;
  o.given = life.given();
  o.given.started = false;
  const std::string not_saved = life.writeSummaryHere(o);
  if (!not_saved.empty()) o.fail(RunStatus::Failed, ErrorKind::Output, why);
  report.line = "wake-up: " + withAlso(why, not_saved);
  return report;
}

/// The steps that woke the robot up are not localized: the filter starts at the pose found, at
/// the last of them, with its covariance; the wake-up's error against the truth there.
void startAtWakeUp(const wakeup::WakeUpRun& woke, const LocalizationOptions& options,
                   LocalizationInputs& inputs, std::vector<Step>& steps, LocalizationWakeUp& wake) {
  const std::size_t used = woke.steps_read;
  const auto& at = inputs.truth.poses[used - 1];
  if (at) {
    const auto e = wakeup::wakeUpError(woke.result.pose, *at);
    wake.error = LocalizationWakeUp::Error{
        inputs.truth.kind, e.xy_m, e.yaw_deg,
        e.xy_m <= options.success_xy && e.yaw_deg <= options.success_yaw_deg};
  }
  inputs.start = woke.result.pose;
  inputs.start_source = "wake-up";
  steps.erase(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(used));
  inputs.truth.poses.erase(inputs.truth.poses.begin(),
                           inputs.truth.poses.begin() + static_cast<std::ptrdiff_t>(used));
}

/// The filter over the steps; returns the stop line ("" when every step was localized).
std::string localizeSteps(Localizer& localizer, const std::vector<Step>& steps,
                          std::ostream& progress_out, const RunHooks& hooks,
                          const ProgressSettings& settings) {
  ProgressReporter progress(progress_out, "localize", settings);
  for (const auto& s : steps) {
    localizer.process(s);
    progress.update(static_cast<double>(localizer.stepsDone()) / steps.size(),
                    localizer.stepsDone(), steps.size(), "");
    if (hooks.on_step) hooks.on_step(s.index);
    if (Cancellation::requested()) {
      progress.finish(false);
      return " after step " + std::to_string(s.index);
    }
  }
  progress.finish(true);
  return "";
}

}  // namespace

LocalizeReport localize(const LocalizeRequest& request, RequestContext context,
                        const RunHooks& hooks) {
  const LocalizeRequest& cli = request;
  LocalizeReport report;
  RunLife life(localizeGiven());
  LocalizeInputs in;
  std::unique_ptr<Localizer> localizer;
  std::optional<LocalizationWakeUp> wake;  ///< summary.json's wake_up block, once looked for
  std::ostringstream no_progress;
  std::ostream& progress_out = hooks.progress_out ? *hooks.progress_out : no_progress;
  const auto ended = [&](RunLife::End end) {
    report.outcome = std::move(end.outcome);
    report.line = std::move(end.line);
    return std::move(report);
  };
  const auto warn = [&](const std::string& line) {
    report.warnings.push_back(line);
    if (hooks.warning) hooks.warning(line);
  };

  try {
    in.rc = loadRunConfig(request, context);
    for (const auto& w : in.rc.warnings) warn(w);
    life.open(in.rc.outdir, cli.common.force);
  } catch (const Error& e) {
    life.openToSayWhy(cli.common.outdir, cli.common.force);
    report.folder = life.path();
    return ended(life.end(e.what(), RunStatus::Failed, errorKindOf(e)));
  } catch (const std::exception& e) {
    return ended(life.endOn(e));  // not one of budget-slam's errors (MRPT's own): nothing written
  }
  report.folder = life.path();
  const RunConfig& rc = in.rc;
  in.progress = hooks.progress;
  in.progress.line_every_s = rc.report.progress_every_s;  // the merged ini's [Report]

  try {
    Cancellation::check();  // a stop request that came while the program started
    writeFileAtomically(life.folder().file("config_used.ini"), configUsed(rc.ini));
    if (!readInputs(cli, progress_out, in))
      return ended(life.endInterrupted(" while reading the rawlog"));
    report.map_landmarks = in.map.landmarks.size();

    std::optional<Pose2> given;
    if (cli.start_pose) given = parseStartPose(*cli.start_pose);
    const auto woke = wakeUpIfNeeded(cli, hooks, given, in, wake);
    if (woke && !woke->found()) {
      life.given().rawlog = rc.rawlog, life.given().map = cli.map_dir;
      return notFound(std::move(report), wake->why_not_found + "; no pose is guessed", life, wake);
    }
    if (woke) given = woke->result.pose.mean;
    auto inputs = resolveLocalization(in.steps, in.in_rawlog, in.truth, in.map.alignment, given,
                                      cli.reference_trajectory.empty() ? nullptr : &in.reference,
                                      cli.reference_trajectory, rc.localization);
    if (woke) startAtWakeUp(*woke, rc.localization, inputs, in.steps, *wake);
    // A path of one pose is a run without history (keep_history = false): no area to score in.
    if (in.map.path.size() >= 2) inputs.mapping_path = in.map.path;
    localizer =
        std::make_unique<Localizer>(rc.ini, rc.localization, in.metric_options.reloc_min_landmarks,
                                    life.folder(), in.map.landmarks, inputs);
    life.setFinisher([&](RunOutcome& o) {
      // Before the first step nothing is worth keeping: the next command replaces it.
      const bool started = localizer->stepsDone() > 0;
      RunGiven given;
      given.map = cli.map_dir, given.started = started;
      o = localizer->finish(o.status, o.kind, o.error, given, wake);
      return localizer->summaryError();
    });
    if (const std::string stop =
            localizeSteps(*localizer, in.steps, progress_out, hooks, in.progress);
        !stop.empty())
      return ended(life.endInterrupted(stop));
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
    report.outcome = localizer->finish(RunStatus::Ok, ErrorKind::None, "",
                                       localizedGiven(in, context.config_label, cli.map_dir), wake);
    // An output that could not be written (a full disk): summary.json says which, if it could.
    if (!localizer->writeError().empty())
      report.line = withAlso(localizer->writeError(), localizer->summaryError());
    return report;
  } catch (const Interrupted&) {
    return ended(life.endInterrupted(" before the first step"));
  } catch (const std::exception& e) {
    return ended(life.endOn(e));
  }
}

}  // namespace budget_slam::runs
