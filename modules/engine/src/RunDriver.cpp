#include "budget_slam/engine/RunDriver.h"

#include <filesystem>
#include <optional>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/ProcessProbes.h"
#include "budget_slam/engine/RunMapContent.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/session/SessionStateFile.h"
#include "budget_slam/session/SessionStateOwner.h"
#include "budget_slam/wakeup/WakeUpRun.h"

namespace budget_slam::runs {
namespace {

std::vector<std::unique_ptr<Reducer>> makeShadows(const mrpt::config::CConfigFileBase& ini,
                                                  const reducers::BudgetOptions& budget) {
  std::vector<std::unique_ptr<Reducer>> out;
  for (const auto& name : budget.shadow_reducers) {
    auto r = reducers::builtinReducers().create(name, ini, budget.seed);
    if (r) out.push_back(std::move(r));
  }
  return out;
}

/// Without per-step history, the relocalization coverage follows at most this many evenly spread
/// steps (bounded memory on lifelong runs; docs/OUTPUTS.md).
constexpr std::size_t kMaxCoverageSteps = 4096;
/// Steps between two releases of the heap's free pages: a release costs a walk over the free
/// chunks and the page faults of reusing what it gave back (under 0.1 ms a step on the lifelong
/// scenario at this spacing); resident memory then exceeds the live heap by the holes reused
/// within this many steps and the partly used pages around free chunks (docs/RESULTS.md,
/// lifelong scenario).
constexpr std::size_t kReleaseHeapEverySteps = 100;

std::size_t relocMinLandmarks(const mrpt::config::CConfigFileBase& ini) {
  metrics::MetricsOptions m;
  m.loadFromConfigFile(ini, metrics::MetricsOptions::kSection);
  return m.reloc_min_landmarks;
}

bool finite(const LandmarkView& l) {
  return l.mean.allFinite() && l.cov.allFinite() && l.obs_mean.allFinite();
}

/// The end of a run as its outputs may hold it: the poses of the steps that completed, and
/// finite estimates only (a diverged filter's NaN reaches no picture, metric, k-means or file),
/// with the landmarks' confirmations when the budget keeps negative evidence.
struct FiniteEnd {
  report::RunEndFiles files;
  std::size_t poses_not_finite = 0, landmarks_not_finite = 0;
};

FiniteEnd finiteEnd(const Backend& backend, const reducers::BudgetManager& manager,
                    std::size_t steps_done, StepIndex last_step) {
  FiniteEnd end;
  const auto finitePose = [](const Pose2& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.phi);
  };
  for (const auto& p : backend.trajectory()) {
    if (steps_done == 0 || p.step > last_step) continue;  // a step cut short
    if (!finitePose(p.pose) || !std::isfinite(p.t))
      ++end.poses_not_finite;
    else
      end.files.trajectory.push_back(p);
  }
  const reducers::NegativeEvidence* negative = manager.negativeEvidence();
  for (const auto& l : backend.landmarks()) {
    if (!finite(l)) {
      ++end.landmarks_not_finite;
      continue;
    }
    end.files.landmarks.push_back(l);
    if (!negative) continue;
    const auto r = negative->records().find(l.id);
    end.files.confirmations.push_back(
        r == negative->records().end()
            ? report::LandmarkConfirmation{l.last_step, 0}
            : report::LandmarkConfirmation{r->second.last_confirmed_step, r->second.misses});
  }
  return end;
}

}  // namespace

RunDriver::RunDriver(const mrpt::config::CConfigFileBase& ini, const BackendRegistry& backends,
                     const DriverSpec& spec, report::OutputFolder folder,
                     std::shared_ptr<const dataset::GroundTruth> truth)
    : save_3d_scene_(spec.save_3d_scene),
      backend_(backends.create(spec.backend, ini, BackendSettings{spec.keep_history})),
      manager_(std::make_unique<reducers::BudgetManager>(
          spec.budget,
          reducers::builtinReducers().create(spec.budget.reducer, ini, spec.budget.seed),
          makeShadows(ini, spec.budget))),
      truth_(std::move(truth)),
      outputs_(std::move(folder)),
      rawlog_name_(spec.rawlog_name),
      heap_release_(kReleaseHeapEverySteps) {
  const auto& budget = spec.budget;
  // The moved-landmark test reads the same reading noise as the backends.
  const wakeup::ReadingNoise noise = wakeup::readingNoiseOf(ini);
  manager_->setReadingNoise(noise.std_range, noise.std_bearing);
  // The observers, in the order they are called: the probes first (their afterDrops closes the
  // step's timed window), the eviction log after the map's counts and the NEES, the periodic
  // scenes last (their title counts the step's drops).
  probes_ = &addObserver<StepProbes>();
  reloc_ = &addObserver<RelocCoverageTracking>(relocMinLandmarks(ini),
                                               spec.keep_history ? 0 : kMaxCoverageSteps);
  map_counts_ = &addObserver<MapCounts>(spec.keep_history);
  if (truth_ && !truth_->path.empty()) addObserver<NeesTracking>(*truth_);
  evictions_ = &addObserver<EvictionLog>(outputs_);
  if (spec.scene_every_steps)
    addObserver<SceneSnapshots>(spec.scene_every_steps, outputs_, [this] {
      return mapContent(backend_->trajectory(), backend_->landmarks(), nullptr);
    });
  // map.png colours the kept landmarks by the picture's clusters ([CoverageReducer], run's seed).
  picture_clusters_.seed = budget.seed;
  picture_clusters_.loadFromConfigFile(ini, reducers::CoverageOptions::kSection);
  report::ReportOptions report_options;
  report_options.loadFromConfigFile(ini, report::ReportOptions::kSection);
  figure_formats_ = report_options.figure_formats;
  figure_title_ = report_options.figure_title;
  if (budget.dump_states)
    manager_->setBeforeDropEvent(
        [this](const Backend& b, StepIndex step) { outputs_.writeState(b, step); });
}

void RunDriver::process(const Step& raw) {
  for (const auto& o : observers_) o->stepStarts();
  // Without the readings of landmarks dropped for good, of refused newcomers still waiting and
  // of landmarks suspected of having moved; a landmark found moved leaves the map here.
  const Step filtered = manager_->admit(*backend_, raw);

  const std::size_t before = backend_->landmarkCount();
  backend_->process(filtered);
  // The landmarks the step's readings went to are in the map now (new ones included).
  StepEvent event{raw, filtered, backend_->lastAssociation(), {}, *backend_};
  for (const auto& o : observers_) o->afterUpdate(event);
  const std::size_t added = backend_->landmarkCount() - before;
  const auto diverged = [](const PoseEstimate& p) {
    return !std::isfinite(p.mean.x) || !std::isfinite(p.mean.y) || !std::isfinite(p.mean.phi) ||
           !p.cov.allFinite();
  };
  if (diverged(backend_->robotPose()))
    throw Error("step " + std::to_string(raw.index) + ": the " + backend_->name() +
                " estimate diverged (the robot pose or its covariance is not finite)");
  event.drops = manager_->enforce(*backend_, filtered, raw);
  heap_release_.afterStep();  // timed with the step: its cost is the run's

  // The row: the observers' columns (the probes' first, which ends the timed window), then the
  // map as the step leaves it and the memory read last.
  report::StepRow row;
  for (const auto& o : observers_) o->afterDrops(event, row);
  row.step = raw.index;
  row.t = raw.t;
  row.landmarks = backend_->landmarkCount();
  row.added = added;
  for (const auto& e : event.drops) ++(e.reason == "refused" ? row.refused : row.dropped);
  row.poses = backend_->poseCount();
  row.pose = backend_->robotPose();
  row.rss_bytes = residentBytes();
  // The row first: a step whose row cannot be written (a full disk) does not count, so that
  // steps.csv, trajectory.tum and summary.json agree on the steps done.
  outputs_.addStep(row);

  ++steps_done_;
  last_step_ = raw.index;
  for (const auto& o : observers_) o->stepDone(event, row);
}

report::MapContent RunDriver::mapContent(const std::vector<TrajectoryPoint>& trajectory,
                                         const std::vector<LandmarkView>& landmarks,
                                         const FinalRelocCoverage* coverage) const {
  const auto& budget = manager_->options();
  std::string title = (rawlog_name_.empty() ? "" : rawlog_name_ + ": ") + backend_->name() +
                      ", reducer " + budget.reducer +
                      (manager_->capped() ? ", cap " + std::to_string(*budget.max_landmarks) : "") +
                      ": " + std::to_string(landmarks.size()) + " landmarks kept, " +
                      std::to_string(evictions()) + " dropped" +
                      (refused() ? ", " + std::to_string(refused()) + " refused" : std::string());
  return runMapContent(std::move(title), trajectory, landmarks, picture_clusters_,
                       evictions_->droppedMarks(), coverage, truth_.get());
}

void RunDriver::restoreSession(const session::SessionState& state) {
  auto* owner = session::sessionOwner(backend_.get());
  if (!owner)
    throw ConfigError("--resume: the " + backend_->name() + " backend keeps no session state");
  owner->restoreSession(state);
  manager_->restoreSession(state);
  state.checkAllRead();
}

void RunDriver::writeSessionState(const session::SessionHeader& header) {
  const auto* owner = session::sessionOwner(backend_.get());
  if (!owner) return;
  session::SessionState state;
  state.header = header;
  owner->saveSession(state);
  manager_->saveSession(state);
  session::writeSessionState(outputs_.folder().file(session::kStateFileName), state);
}

void RunDriver::complete() {
  if (completed_) return;
  completed_ = true;
  // The reducer's end-of-run event (mi objective mode: Choudhary et al.'s active minimization),
  // then the backend's (the graph's solve to the batch optimum).
  if (steps_done_ > 0) {
    const auto drops = manager_->finish(*backend_, last_step_);
    for (const auto& o : observers_) o->endOfRunDrops(drops);
  }
  Cancellation::check();  // drops cut short by a stop request are logged above
  if (PoseHistoryBackend* h = poseHistory(backend_.get())) h->finish();
}

RunOutcome RunDriver::finish(RunStatus status, ErrorKind kind, const std::string& error,
                             std::size_t steps_in_rawlog, const RunGiven& given) {
  if (status == RunStatus::Ok) {
    complete();
    Cancellation::check();  // a stop request before the outputs: the run ends as interrupted
  }
  FiniteEnd end = finiteEnd(*backend_, *manager_, steps_done_, last_step_);
  report::RunEndFiles& files = end.files;
  const std::size_t poses_not_finite = end.poses_not_finite,
                    landmarks_not_finite = end.landmarks_not_finite;
  const std::vector<TrajectoryPoint>& trajectory = files.trajectory;
  const std::vector<LandmarkView>& landmarks = files.landmarks;

  // Every output is attempted; the first failure (a full disk) is the run's error. A run that
  // failed before its first step has no result: no file that looks like one (an empty map.png,
  // trajectory.tum, map.3Dscene), only summary.json saying why (issue 35).
  report::RunOutputs::EndFilesResult written;
  if (steps_done_ == 0 && status != RunStatus::Ok) {
    outputs_.discardStepFiles();
  } else {
    const FinalRelocCoverage& reloc = reloc_->settle(*backend_);
    files.map = [&] {
      auto map = mapContent(trajectory, landmarks, &reloc);
      if (!figure_title_) map.title.clear();
      return map;
    };
    files.scene = save_3d_scene_;
    files.figure_formats = figure_formats_;
    if (save_3d_scene_) files.robot = backend_->robotPose().mean;
    files.truth = truth_.get();
    files.steps_in_rawlog = steps_in_rawlog;
    written = outputs_.writeEndFiles(files);
  }
  std::string first_error = written.first_error;

  RunOutcome o;
  o.status = status, o.kind = kind, o.error = error;
  if (o.ok() && (poses_not_finite || landmarks_not_finite))
    o.fail(RunStatus::Failed, ErrorKind::Diverged,
           "the " + backend_->name() + " estimate is not finite at the end of the run (" +
               std::to_string(poses_not_finite) + " poses, " +
               std::to_string(landmarks_not_finite) + " landmarks)");
  if (o.ok() && !first_error.empty()) o.fail(RunStatus::Failed, ErrorKind::Output, first_error);
  o.files_not_written = written.not_written;

  const auto& budget = manager_->options();
  RunOutcome::Run& run = o.run.emplace();
  run.backend = backend_->name();
  run.reducer = budget.reducer;
  if (manager_->capped()) run.cap = *budget.max_landmarks;
  run.counts.steps = steps_done_;
  run.counts.landmarks_final = landmarks.size();
  run.counts.landmarks_not_finite = landmarks_not_finite;
  run.counts.poses_not_finite = poses_not_finite;
  run.counts.poses_kept = backend_->poseCount();
  run.counts.poses_marginalized = manager_->posesMarginalized();
  run.agreement = agreementJson(*manager_);
  run.shadow_failures = shadowFailuresJson(*manager_);
  if (truth_ && !truth_->empty()) {
    GroundTruthOutcome& gt = o.ground_truth.emplace();
    gt.landmarks_file = truth_->landmarks_file;
    gt.path_file = truth_->path_file;
  }
  // The observers' blocks: timings, relocalization, the map's and the drops' counts, the NEES.
  for (const auto& ob : observers_) ob->fill(o, steps_in_rawlog);

  if (o.ground_truth && steps_done_ > 0) {
    GroundTruthOutcome& gt = *o.ground_truth;
    try {
      gt.errors = metrics::groundTruthErrors(trajectory, landmarks, *truth_, steps_in_rawlog);
    } catch (const Error& x) {
      if (first_error.empty()) first_error = x.what();  // a bug: inputs are finite here
    }
    // Where the ground truth's frame sits in the map's (budget-slam localize starts another
    // traversal's robot there; docs/OUTPUTS.md).
    alignment_ = metrics::mapAlignment(landmarks, trajectory, *truth_, steps_in_rawlog);
    gt.alignment = alignment_;
  }
  o.given = given;
  try {
    writeSummary(outputs_.folder().file("summary.json"), o);
  } catch (const std::exception& e) {
    summary_error_ = exceptionLine(e);
    if (first_error.empty()) first_error = summary_error_;
  }
  write_error_ = first_error;
  return o;
}

}  // namespace budget_slam::runs
