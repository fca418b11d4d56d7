// runs::runSlam: one `budget-slam run` from its typed specification (docs/ARCHITECTURE.md "A run").
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/engine/RawlogSteps.h"
#include "budget_slam/engine/RunLife.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/Runs.h"
#include "budget_slam/session/SessionStateFile.h"

namespace budget_slam::runs {

namespace {

/// What a run ended with: `end`'s outcome and line in `report`.
RunReport ended(RunReport report, RunLife::End end) {
  report.outcome = std::move(end.outcome);
  report.line = std::move(end.line);
  return report;
}

/// A run between its driver's making and its end phase: the rawlog read step by step into the
/// driver (after the steps skipped), with progress, stopping on a stop request.
class StepLoop {
 public:
  StepLoop(const RunSpec& spec, RunDriver& driver, std::size_t first_index)
      : spec_(spec), driver_(driver), first_index_(first_index), reader_(spec.rawlog) {
    // A signal ends the reading within one read of the file, even inside a large object.
    reader_.setStopCheck([] { return Cancellation::requested(); });
  }

  /// Runs the steps; returns the stop line ("" when the steps ran to their end). Throws
  /// InputError when no step is left to run or the rawlog holds no bearing-range reading.
  std::string run(std::ostream& progress_out, const RunHooks& hooks, RunReport& result) {
    const std::size_t skip = spec_.skip_steps + spec_.wake_up_steps;
    std::size_t skipped = 0;
    while (skipped < skip && reader_.next()) ++skipped;
    const std::size_t limit = spec_.max_steps;
    ProgressReporter progress(progress_out, "run", hooks.progress);
    while (limit == 0 || steps_ < limit) {
      auto step = reader_.next();
      if (step) step->index = static_cast<StepIndex>(first_index_ + steps_++);
      if (!step && reader_.stopped()) {
        progress.finish(false);
        result.steps = steps_;
        return " while reading step " + std::to_string(reader_.stepsRead());
      }
      if (!step) break;
      steps_read_ = reader_.stepsRead();
      driver_.process(*step);
      result.steps = steps_;
      // With --max-steps the share of the steps to do, else of the rawlog's bytes read.
      progress.update(limit ? double(steps_) / double(limit) : reader_.progress(), steps_, limit,
                      std::to_string(driver_.backend().landmarkCount()) + " landmarks in the map");
      if (hooks.on_step) hooks.on_step(step->index);
      if (Cancellation::requested()) {
        progress.finish(false);
        return afterLastStep(driver_);
      }
    }
    progress.finish(true);
    // Steps skipped (--skip-steps, a wake-up's) that leave none to run: a mistake, not a session.
    if (steps_ == 0 && skip > 0)
      throw InputError("--skip-steps " + std::to_string(spec_.skip_steps) + ": rawlog '" +
                       spec_.rawlog + "' holds " + std::to_string(skipped) + " step" +
                       (skipped == 1 ? "" : "s") +
                       (spec_.wake_up_steps
                            ? " (" + std::to_string(spec_.wake_up_steps) + " read by the wake-up)"
                            : std::string()) +
                       "; none is left to run");
    requireBearingRange(reader_, spec_.rawlog);
    return "";
  }

  std::size_t steps() const { return steps_; }           ///< steps of this session
  std::size_t stepsRead() const { return steps_read_; }  ///< the rawlog's steps read

  /// " after step N" (the last step whose outputs are written), or " before the first step".
  static std::string afterLastStep(const RunDriver* driver) {
    const auto last = driver ? driver->lastStep() : std::nullopt;
    return last ? " after step " + std::to_string(*last) : std::string(" before the first step");
  }
  static std::string afterLastStep(const RunDriver& driver) { return afterLastStep(&driver); }

 private:
  const RunSpec& spec_;
  RunDriver& driver_;
  std::size_t first_index_;
  dataset::RawlogReader reader_;
  std::size_t steps_ = 0, steps_read_ = 0;
};

/// The state a next session continues from: after the last step's drops, before the end-of-run
/// drops and the final solve (which a one-shot run would not make here). A state the reader would
/// refuse (a robot covariance that is not positive definite: a robot that has not moved yet with
/// odometry noise in some axes only) is not written; the run itself is fine. summary.json says
/// why; --resume on it says there is no such file.
void writeSessionState(const RunSpec& spec, RunDriver& driver, std::size_t first_index,
                       std::size_t steps, RunLife& life, const RunHooks& hooks) {
  session::SessionHeader header;
  header.writer = spec.writer;
  header.backend = spec.driver.backend;
  header.rawlog = spec.rawlog;
  header.sessions = spec.resumed ? spec.resumed->header.sessions + 1 : 1;
  header.first_step = static_cast<std::int64_t>(first_index);
  header.next_step = static_cast<std::int64_t>(first_index + steps);
  header.resume_options = spec.resume_options;
  try {
    driver.writeSessionState(header);
    life.given().session_state = SessionStateWritten{true, ""};
  } catch (const Error& e) {
    life.given().session_state = SessionStateWritten{false, printable(e.what())};
    if (hooks.note)
      hooks.note(std::string(session::kStateFileName) + " not written: " + printable(e.what()));
  }
}

}  // namespace

RunReport runSlam(const RunSpec& spec, const RunHooks& hooks) {
  RunReport result;
  RunLife life(spec.given);
  std::unique_ptr<RunDriver> driver;
  std::optional<StepLoop> loop;
  try {
    life.open(spec.outdir, spec.force);
  } catch (const Error& e) {
    return ended(std::move(result), life.end(e.what(), RunStatus::Failed, errorKindOf(e)));
  }
  result.folder = life.path();
  // Recorded in summary.json; said as a note (an error stays one line).
  if (const std::string note = life.earlierRunNote(); !note.empty() && hooks.note) hooks.note(note);

  // A stop request that came while the program started.
  if (Cancellation::requested())
    return ended(std::move(result), life.endInterrupted(StepLoop::afterLastStep(driver.get())));
  bool end_phase = false;
  std::ostringstream no_progress;
  std::ostream& progress_out = hooks.progress_out ? *hooks.progress_out : no_progress;
  try {
    writeFileAtomically(life.folder().file("config_used.ini"), configUsed(spec.ini));
    // Step indices run on across sessions. A resumed session on the same rawlog from the step
    // the last one stopped at (--skip-steps = its next step) keeps the rawlog's indices and so
    // its ground truth; on another rawlog the ground truth's rows would not match them.
    const std::size_t first_index =
        (spec.resumed ? spec.resumed->header.next_step : spec.skip_steps) + spec.wake_up_steps;
    const bool truth_aligned = first_index == spec.skip_steps + spec.wake_up_steps;
    auto truth = std::make_shared<dataset::GroundTruth>(
        truth_aligned ? dataset::loadGroundTruth(spec.rawlog, spec.ground_truth_file,
                                                 spec.ground_truth_file_robot)
                      : dataset::GroundTruth());
    driver =
        std::make_unique<RunDriver>(spec.ini, *spec.backends, spec.driver, life.folder(), truth);
    life.setFinisher([&](RunOutcome& o) {
      o.given.started = driver->lastStep().has_value();
      o = driver->finish(o.status, o.kind, o.error, loop ? loop->stepsRead() : 0, o.given);
      return driver->summaryError();
    });
    if (spec.resumed) driver->restoreSession(*spec.resumed);

    loop.emplace(spec, *driver, first_index);
    if (const std::string stop = loop->run(progress_out, hooks, result); !stop.empty())
      return ended(std::move(result), life.endInterrupted(stop));
    writeSessionState(spec, *driver, first_index, loop->steps(), life, hooks);

    end_phase = true;
    if (hooks.on_end_phase) hooks.on_end_phase();
    RunGiven& given = life.given();
    given.started = driver->lastStep().has_value();
    result.outcome = driver->finish(RunStatus::Ok, ErrorKind::None, "", loop->stepsRead(), given);
    // Shadow reducers are only logged; their failures end nothing, but are never silent.
    for (const auto& f : driver->budget().shadowFailures())
      result.warnings.push_back(shadowFailureLine(f));
    if (!result.outcome.ok() || !driver->writeError().empty()) {
      // An output that could not be written (a full disk): the run failed, summary.json says so
      // when it could still be written.
      if (result.outcome.ok())
        result.outcome.fail(RunStatus::Failed, ErrorKind::Output, driver->writeError());
      result.line = withAlso(result.outcome.error, driver->summaryError());
      return result;
    }
    result.final_pose = driver->backend().robotPose().mean;
    result.landmarks = driver->backend().landmarkCount();
    return result;
  } catch (const Interrupted&) {
    return ended(std::move(result),
                 life.endInterrupted((end_phase ? " in the end phase," : std::string()) +
                                     StepLoop::afterLastStep(driver.get())));
  } catch (const std::exception& e) {
    return ended(std::move(result), life.endOn(e));
  }
}

}  // namespace budget_slam::runs
