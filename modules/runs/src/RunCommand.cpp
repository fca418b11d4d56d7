// runs::run: a `run` from its request, around runSlam (docs/ARCHITECTURE.md "A run").
#include <filesystem>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/engine/RunLife.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/RunSession.h"
#include "budget_slam/runs/RunSpecs.h"
#include "budget_slam/runs/Runs.h"

namespace budget_slam::runs {

RunReport run(const RunRequest& request, RequestContext context, const RunHooks& hooks) {
  const std::string& label = context.config_label;
  RunGiven given;  // what the run was given, in summary.json
  given.config = label;
  if (!request.common.rawlog.empty()) given.rawlog = request.common.rawlog;
  // A run that ended before runSlam: its one line.
  const auto ended = [](RunStatus status, ErrorKind kind, const std::string& line) {
    RunReport r;
    r.outcome.fail(status, kind, line);
    r.line = line;
    return r;
  };
  const auto warn = [&](const std::string& line) {
    if (hooks.warning) hooks.warning(line);
  };

  RunConfig rc;
  try {
    rc = loadRunConfig(request, context);
  } catch (const std::exception& e) {
    // Error: a bad value, key or file; anything else (MRPT's own exceptions) in one line.
    const std::string why = printable(
        dynamic_cast<const Error*>(&e) ? std::string(e.what()) : label + ": " + failureLine(e));
    RunLife life(given);
    life.openToSayWhy(request.common.outdir, request.common.force);
    RunLife::End end = life.end(why, RunStatus::Failed, errorKindOf(e));
    RunReport r;
    r.outcome = std::move(end.outcome);
    r.line = std::move(end.line);
    return r;
  }

  for (const auto& w : rc.warnings) warn(w);
  RunSpec spec;
  spec.given.rawlog = rc.rawlog, spec.given.sidecar_ini = rc.sidecar, spec.given.config = label;
  // A session to continue is read and checked before the output folder is touched: a bad state
  // file or a mismatched option is one line, exit 1, and nothing is written (docs/OUTPUTS.md).
  spec.resume_options = resumeOptions(rc.ini);
  if (!request.resume.empty()) {
    try {
      std::error_code ec;
      if (std::filesystem::equivalent(request.resume, rc.outdir, ec))
        throw ConfigError("--resume " + request.resume +
                          ": the output folder must be another one (the saved session stays)");
      spec.resumed = loadResumeState(request.resume, rc.mapping.backend, spec.resume_options);
    } catch (const std::exception& e) {
      return ended(RunStatus::Failed, errorKindOf(e), printable(e.what()));
    }
    spec.given.resumed_from = request.resume;
    if (request.wake_up) {
      // Before any output: a robot not found is one line, exit 1, nothing written.
      try {
        const WakeUpOutcome w = wakeUpOnMap(rc, *spec.resumed, request.skip_steps);
        spec.given.wake_up = w.block;
        if (!w.found) return ended(RunStatus::Failed, ErrorKind::Input, "--wake-up: " + w.why);
        spec.wake_up_steps = w.steps;
      } catch (const Interrupted&) {
        // Before any output, as a robot not found: nothing written, exit 130.
        return ended(RunStatus::Interrupted, ErrorKind::Stopped,
                     std::string("interrupted by ") + Cancellation::signalName() +
                         " while waking up on the saved map");
      } catch (const std::exception& e) {
        return ended(RunStatus::Failed, errorKindOf(e), printable(e.what()));
      }
    }
  }
  spec.ini = rc.ini;
  spec.backends = &builtinBackends();
  spec.driver = driverSpec(rc);
  spec.rawlog = rc.rawlog;
  spec.ground_truth_file = rc.mapping.ground_truth_file;
  spec.ground_truth_file_robot = rc.mapping.ground_truth_file_robot;
  spec.outdir = rc.outdir;
  spec.force = request.common.force;
  spec.max_steps = rc.mapping.max_steps;
  spec.skip_steps = request.skip_steps;
  spec.writer = context.writer;

  RunHooks slam = hooks;
  slam.progress.line_every_s = rc.report.progress_every_s;
  RunReport report = runSlam(spec, slam);
  for (const auto& w : report.warnings) warn(w);
  return report;
}

}  // namespace budget_slam::runs
