// runs::runSlam: one `budget-slam run` from its typed specification (docs/ARCHITECTURE.md "A run").
#include <set>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/Runs.h"
#include "budget_slam/runs/SummaryJson.h"
#include "budget_slam/session/SessionStateFile.h"

namespace budget_slam::runs {
namespace {

std::string joined(const std::set<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
}

}  // namespace

std::string writeEarlySummary(const std::string& outdir, bool force, RunOutcome outcome) {
  if (outdir.empty()) return "";
  std::optional<report::OutputFolder> folder;
  try {
    folder.emplace(outdir, force);
  } catch (const Error&) {
    return "";  // the folder's own error is not this run's: the run's line says why it failed
  }
  try {
    if (!folder->earlierRun().empty()) outcome.given["earlier_run_moved_to"] = folder->earlierRun();
    writeSummary(folder->file("summary.json"), outcome);
  } catch (const std::exception& e) {
    return failureLine(e);
  }
  return "";
}

RunReport runSlam(const RunSpec& spec, const RunHooks& hooks) {
  RunReport result;
  std::optional<report::OutputFolder> folder;
  std::unique_ptr<RunDriver> driver;
  std::size_t steps_read = 0;
  nlohmann::json given = spec.given;

  // Ends the run as `status` for the reason `why`: summary.json (through the driver when there
  // is one) and the one line.
  const auto fail = [&](const std::string& why, RunStatus status, ErrorKind kind) {
    // One printable line whatever the message echoes (corrupt bytes of a file, say), which also
    // says why summary.json could not be written when it could not.
    const std::string msg = printable(why);
    std::string not_saved;
    try {
      // A run that ended before its first step made nothing to keep: the next run into the
      // folder replaces its files (report/OutputFolder.h).
      given["started"] = driver && driver->lastStep().has_value();
      if (driver) {
        result.outcome = driver->finish(status, kind, msg, steps_read, given);
        not_saved = driver->summaryError();
      } else {
        result.outcome.fail(status, kind, msg);
        result.outcome.given = given;
        if (folder) {
          if (!folder->earlierRun().empty())
            result.outcome.given["earlier_run_moved_to"] = folder->earlierRun();
          writeSummary(folder->file("summary.json"), result.outcome);
        }
      }
    } catch (const std::exception& e) {
      not_saved = failureLine(e);
    }
    // The outcome is the one asked for, whatever the driver made of it.
    result.outcome.status = status, result.outcome.kind = kind, result.outcome.error = msg;
    result.line = withAlso(msg, not_saved);
    return result;
  };
  // Where a stop request (Ctrl-C) found the run: the last step whose outputs are written.
  const auto interrupted = [&](const char* where) {
    const auto last = driver ? driver->lastStep() : std::nullopt;
    return std::string("interrupted by ") + Cancellation::signalName() + where +
           (last ? " after step " + std::to_string(*last) : std::string(" before the first step"));
  };
  const auto note = [&](const std::string& line) {
    if (hooks.note) hooks.note(line);
  };

  try {
    folder.emplace(spec.outdir, spec.force);
  } catch (const Error& e) {
    return fail(e.what(), RunStatus::Failed, errorKindOf(e));
  }
  result.folder = folder->path();
  if (!folder->earlierRun().empty()) {
    // Recorded in summary.json; said as a note (an error stays one line).
    given["earlier_run_moved_to"] = folder->earlierRun();
    note(folder->path() + " held an earlier run; its files were moved to " + folder->earlierRun() +
         "/");
  }

  // A stop request that came while the program started.
  if (Cancellation::requested())
    return fail(interrupted(""), RunStatus::Interrupted, ErrorKind::Stopped);
  bool end_phase = false;
  std::ostringstream no_progress;
  std::ostream& progress_out = hooks.progress_out ? *hooks.progress_out : no_progress;
  try {
    writeFileAtomically(folder->file("config_used.ini"), configUsed(spec.ini));
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
    driver = std::make_unique<RunDriver>(spec.ini, *spec.backends, spec.driver, *folder, truth);
    if (spec.resumed) driver->restoreSession(*spec.resumed);

    dataset::RawlogReader reader(spec.rawlog);
    // A signal ends the reading within one read of the file, even inside a large object.
    reader.setStopCheck([] { return Cancellation::requested(); });
    const std::size_t skip = spec.skip_steps + spec.wake_up_steps;
    std::size_t skipped = 0;
    while (skipped < skip && reader.next()) ++skipped;
    const std::size_t limit = spec.max_steps;
    ProgressReporter progress(progress_out, "run", hooks.progress);
    std::size_t session_steps = 0;
    while (limit == 0 || session_steps < limit) {
      auto step = reader.next();
      if (step) step->index = static_cast<StepIndex>(first_index + session_steps++);
      if (!step && reader.stopped()) {
        progress.finish(false);
        result.steps = session_steps;
        return fail(std::string("interrupted by ") + Cancellation::signalName() +
                        " while reading step " + std::to_string(reader.stepsRead()),
                    RunStatus::Interrupted, ErrorKind::Stopped);
      }
      if (!step) break;
      steps_read = reader.stepsRead();
      driver->process(*step);
      result.steps = session_steps;
      // With --max-steps the share of the steps to do, else of the rawlog's bytes read.
      progress.update(limit ? double(session_steps) / double(limit) : reader.progress(),
                      session_steps, limit,
                      std::to_string(driver->backend().landmarkCount()) + " landmarks in the map");
      if (hooks.on_step) hooks.on_step(step->index);
      if (Cancellation::requested()) {
        progress.finish(false);
        return fail(interrupted(""), RunStatus::Interrupted, ErrorKind::Stopped);
      }
    }
    progress.finish(true);
    // Steps skipped (--skip-steps, a wake-up's) that leave none to run: a mistake, not a session.
    if (session_steps == 0 && skip > 0)
      throw InputError(
          "--skip-steps " + std::to_string(spec.skip_steps) + ": rawlog '" + spec.rawlog +
          "' holds " + std::to_string(skipped) + " step" + (skipped == 1 ? "" : "s") +
          (spec.wake_up_steps ? " (" + std::to_string(spec.wake_up_steps) + " read by the wake-up)"
                              : std::string()) +
          "; none is left to run");
    if (reader.bearingRangeSteps() == 0)
      throw InputError("rawlog '" + spec.rawlog +
                       "' holds no CObservationBearingRange (it holds: " +
                       joined(reader.observationClasses()) + ")");

    // The state a next session continues from: after the last step's drops, before the
    // end-of-run drops and the final solve (which a one-shot run would not make here).
    session::SessionHeader header;
    header.writer = spec.writer;
    header.backend = spec.driver.backend;
    header.rawlog = spec.rawlog;
    header.sessions = spec.resumed ? spec.resumed->header.sessions + 1 : 1;
    header.first_step = static_cast<std::int64_t>(first_index);
    header.next_step = static_cast<std::int64_t>(first_index + session_steps);
    header.resume_options = spec.resume_options;
    // A state the reader would refuse (a robot covariance that is not positive definite: a
    // robot that has not moved yet with odometry noise in some axes only) is not written; the
    // run itself is fine. summary.json says why; --resume on it says there is no such file.
    try {
      driver->writeSessionState(header);
      given["session_state"] = {{"written", true}};
    } catch (const Error& e) {
      given["session_state"] = {{"written", false}, {"why", printable(e.what())}};
      note(std::string(session::kStateFileName) + " not written: " + printable(e.what()));
    }

    end_phase = true;
    if (hooks.on_end_phase) hooks.on_end_phase();
    given["started"] = driver->lastStep().has_value();
    result.outcome = driver->finish(RunStatus::Ok, ErrorKind::None, "", steps_read, given);
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
    return fail(interrupted(end_phase ? " in the end phase," : ""), RunStatus::Interrupted,
                ErrorKind::Stopped);
  } catch (const std::exception& e) {
    return fail(failureLine(e), RunStatus::Failed, errorKindOf(e));
  }
}

}  // namespace budget_slam::runs
