// runs::compare: a `compare` from its request (docs/ARCHITECTURE.md "A compare"): the rawlog
// parsed once, the unreduced reference and one run per reducer in parallel threads, then every
// run measured against the reference and the ground truth, and the comparison's files.
#include <algorithm>
#include <filesystem>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/Instruments.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/report/RunFiles.h"
#include "budget_slam/runs/BuiltinBackends.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/OfflineOptimum.h"
#include "budget_slam/runs/ProcessProbes.h"
#include "budget_slam/runs/Relocalize.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/RunSpecs.h"
#include "budget_slam/runs/ShadowReducers.h"
#include "budget_slam/runs/SummaryJson.h"

namespace budget_slam::runs {
namespace {

/// --relocalize: every final map of an ok run (the reference's too) localizes each traversal;
/// fills the reloc_* columns of `rows` and adds the failed localizations to `outcome`.
std::vector<RelocalizationResult> relocalizeMaps(
    const CompareRuns& compared, const std::vector<Traversal>& traversals,
    const std::vector<TrajectoryPoint>* reference, const Request& request,
    std::vector<report::ComparisonRow>& rows, CompareOutcome& outcome, ProgressReporter& progress) {
  // One mapped area for every map (the reference run's path, when it ended ok), so that every
  // map is scored on the same steps.
  std::vector<mrpt::math::TPose2D> reference_path;
  if (compared.front()->ok())
    for (const auto& p : compared.front()->driver->backend().trajectory())
      reference_path.push_back(p.pose);
  std::vector<MapOfRun> maps;
  for (const auto& r : compared)
    if (r->ok()) {
      std::vector<mrpt::math::TPose2D> own;
      if (reference_path.empty())
        for (const auto& p : r->driver->backend().trajectory()) own.push_back(p.pose);
      maps.push_back({r->name, r->driver->folder().path(), r->driver->backend().landmarks(),
                      r->driver->mapAlignment(), reference_path.empty() ? own : reference_path});
    }
  auto relocalized = relocalizeAll(maps, traversals, reference, request.reference_trajectory,
                                   request.threads, request.force, &progress);
  addRelocalizationColumns(rows, relocalized, kReferenceRun);
  for (const auto& r : relocalized)
    if (r.status != RunStatus::Ok)
      outcome.add(r.status, r.kind,
                  "run '" + r.run + "', --relocalize '" + r.traversal + "': " + r.error, true);
  return relocalized;
}

/// --offline-optimum: offline_optimum.csv; returns its table (for comparison.md).
std::string writeOfflineOptimumFiles(const report::OutputFolder& top, const RunConfig& rc,
                                     const CompareRuns& compared, const std::vector<Step>& steps) {
  if (!rc.budget.max_landmarks) throw InputError("--offline-optimum needs a cap (not --cap none)");
  std::vector<FinalMap> maps;
  for (const auto& r : compared) {
    FinalMap m{r->name, {}};
    for (const auto& l : r->driver->backend().landmarks()) m.kept.push_back(l.id);
    maps.push_back(std::move(m));
  }
  return writeOfflineOptimum(top.file("offline_optimum.csv"), rc.ini, steps,
                             compared.front()->driver->onlinePoses(), maps,
                             *rc.budget.max_landmarks);
}

/// "seed 1", "seeds 1 to 5" or "3 seeds" (comparison.md's title).
std::string seedText(const RunConfig& rc, const std::vector<std::uint64_t>& seeds) {
  if (seeds.empty()) return "seed " + std::to_string(rc.budget.seed);
  const bool range = seeds.back() - seeds.front() + 1 == seeds.size();
  return seeds.size() == 1 ? "seed " + std::to_string(seeds.front())
         : range ? "seeds " + std::to_string(seeds.front()) + " to " + std::to_string(seeds.back())
                 : std::to_string(seeds.size()) + " seeds";
}

}  // namespace

CompareReport compare(const Request& request, RequestContext context, const RunHooks& hooks) {
  const std::string& label = context.config_label;
  CompareReport result;
  CompareOutcome& outcome = result.outcome;
  std::optional<report::OutputFolder> top;
  CompareRuns compared;
  const auto warn = [&](const std::string& line) {
    if (hooks.warning) hooks.warning(line);
  };
  // A failure before the runs started: one line, the top summary.json and those of the runs made
  // so far say why (and that nothing started: the next compare into the folder replaces them).
  const auto fail = [&](const std::string& why, RunStatus status, ErrorKind kind) {
    const std::string msg = printable(why);  // one line, valid UTF-8 (summary.json)
    std::string not_saved;
    RunOutcome o;
    o.fail(status, kind, msg);
    o.given = {{"started", false}};
    if (top) {
      result.folder = top->path();
      // Each run made so far says its own end: it did not start, and why (issue 35: they carried
      // another run's error as their own).
      for (const auto& r : compared) {
        try {
          r->driver->finish(status, kind, "the comparison did not start: " + msg, 0, o.given);
        } catch (const std::exception&) {
          // its line is this failure's line; the top summary says it
        }
      }
      try {
        writeSummary(top->file("summary.json"), o);
      } catch (const std::exception& e) {
        not_saved = failureLine(e);
      }
    }
    outcome.status = status, outcome.kind = kind, outcome.first_error = msg;
    outcome.lines = {{status == RunStatus::Interrupted ? CompareLine::Kind::Interrupted
                                                       : CompareLine::Kind::Error,
                      withAlso(msg, not_saved)}};
    return std::move(result);
  };
  const auto failed = [&](const std::exception& e, const std::string& why) {
    return fail(why, RunStatus::Failed, errorKindOf(e));
  };

  RunConfig rc;
  std::vector<std::string> names = request.reducers;
  try {
    rc = loadRunConfig(request, context);
    // --reducers was checked with the request (checkRequest).
    if (names.empty())
      for (const auto& n : reducers::builtinReducers().names())
        if (n != "none" && !reducers::isInstrument(n)) names.push_back(n);
    for (const auto& n : names) checkCapFor(rc, request, n, label);
  } catch (const Error& e) {
    if (!request.outdir.empty()) try {
        top.emplace(request.outdir, request.force);
      } catch (const Error&) {
      }
    return failed(e, e.what());
  }
  for (const auto& w : rc.warnings) warn(w);
  ProgressSettings progress_settings = hooks.progress;
  progress_settings.line_every_s = rc.report.progress_every_s;
  std::ostringstream no_progress;
  std::ostream& progress_out = hooks.progress_out ? *hooks.progress_out : no_progress;
  metrics::MetricsOptions metric_options;
  try {
    metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
    top.emplace(rc.outdir, request.force);
  } catch (const Error& e) {
    return failed(e, e.what());
  }
  result.folder = top->path();
  if (!top->earlierRun().empty() && hooks.note)
    hooks.note(top->path() + " held an earlier run; its files were moved to " + top->earlierRun() +
               "/");

  std::shared_ptr<dataset::GroundTruth> truth;
  std::vector<Step> steps;
  std::vector<Traversal> traversals;           // --relocalize
  std::vector<TrajectoryPoint> reference_tum;  // --reference-trajectory
  try {
    Cancellation::check();  // a stop request that came while the program started
    traversals = loadTraversals(context.params, request, label);
    if (!request.reference_trajectory.empty())
      reference_tum = report::readTrajectoryTum(request.reference_trajectory, 50'000'000);
    writeFileAtomically(top->file("config_used.ini"), configUsed(rc.ini));
    truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(
        rc.rawlog, rc.mapping.ground_truth_file, rc.mapping.ground_truth_file_robot));
    ProgressReporter reading(progress_out, "reading the rawlog", progress_settings);
    auto read = readSteps(rc.rawlog, rc.mapping.max_steps, reading);
    if (!read)
      return fail(
          std::string("interrupted by ") + Cancellation::signalName() + " while reading the rawlog",
          RunStatus::Interrupted, ErrorKind::Stopped);
    steps = std::move(*read);
    makeRuns(rc.ini, builtinBackends(), driverSpec(rc), names, request.seeds, *top, request.force,
             truth, compared);
  } catch (const Interrupted&) {
    return fail(
        std::string("interrupted by ") + Cancellation::signalName() + " before the first step",
        RunStatus::Interrupted, ErrorKind::Stopped);
  } catch (const Error& e) {
    return failed(e, e.what());
  } catch (const std::exception& e) {
    return failed(e, failureLine(e));
  }
  result.started = true;

  // One thread a core, each taking whole runs; every run's outputs are written whatever its end.
  const std::size_t wanted = request.threads ? request.threads : availableCpus();
  const std::size_t threads =
      std::max<std::size_t>(1, std::min<std::size_t>(wanted, compared.size()));
  if (const std::string note = largeReferenceNote(rc.mapping.backend, distinctLandmarkIds(steps));
      !note.empty() && hooks.note)
    hooks.note(note);
  {
    std::size_t traversal_steps = 0;
    for (const auto& t : traversals) traversal_steps += t.steps.size();
    // Said with the runs' ETA, which does not cover it (its own progress follows).
    const std::string after = traversals.empty()
                                  ? ""
                                  : "then relocalization: " + std::to_string(compared.size()) +
                                        " maps on " + std::to_string(traversal_steps) + " steps";
    ProgressReporter progress(progress_out, "compare", progress_settings);
    const std::string fewer =
        runInThreads(compared, steps, threads, hooks.on_end_phase, progress, after);
    if (!fewer.empty()) warn(fewer + "; the runs went on in them");
  }

  // Metrics against the reference, then every run's files.
  const CompareRun& ref = *compared.front();
  const std::size_t ref_landmarks = ref.driver->backend().landmarkCount();
  const std::size_t ref_poses = ref.driver->backend().poseCount();
  // Without sensor IDs, a final map's coverage goes through the reference run's association
  // (docs/OUTPUTS.md, "Relocalization coverage").
  if (ref.ok() && withoutLandmarkIds(steps))
    for (const auto& r : compared)
      if (r->ok())
        r->driver->setFinalRelocCoverage(relocCoverageThroughReference(
            *ref.driver, *r->driver, metric_options.reloc_match_chi2));
  std::vector<report::ComparisonRow>& rows = result.rows;
  for (const auto& r : compared) {
    const nlohmann::json extra = {
        {"rawlog", rc.rawlog}, {"sidecar_ini", rc.sidecar}, {"config", label}, {"run", r->name}};
    const auto m = finishRun(*r, ref, steps.size(), metric_options.eig_max_rows, extra);
    // The reference's failure fails every comparison, but the others' errors are their own.
    if (!r->ok()) outcome.add(r->status, r->kind, "run '" + r->name + "': " + r->error, false);
    for (const auto& f : r->driver->budget().shadowFailures())
      outcome.lines.push_back(
          {CompareLine::Kind::Warning, "run '" + r->name + "': " + shadowFailureLine(f)});
    rows.push_back(comparisonRow(*r, m, ref_landmarks, ref_poses));
  }

  std::vector<RelocalizationResult> relocalized;
  if (!traversals.empty()) {
    ProgressReporter progress(progress_out, "relocalize", progress_settings);
    relocalized = relocalizeMaps(compared, traversals,
                                 request.reference_trajectory.empty() ? nullptr : &reference_tum,
                                 request, rows, outcome, progress);
  }

  // Every output is attempted; the first that cannot be written (a full disk) fails the
  // comparison in one line, and summary.json, written last, says which were not.
  std::vector<std::string> not_written;
  const auto attempt = [&](const std::string& name, const std::function<void()>& write) {
    try {
      write();
    } catch (const std::exception& e) {
      if (not_written.empty())
        outcome.add(RunStatus::Failed, ErrorKind::Output, report::outputFailureLine(e), true);
      not_written.push_back(name);
    }
  };
  attempt("comparison.csv", [&] { report::writeComparisonCsv(top->file("comparison.csv"), rows); });
  if (!traversals.empty())
    attempt("relocalization.csv",
            [&] { writeRelocalizationCsv(top->file("relocalization.csv"), relocalized); });
  const std::string title = "budget-slam compare: " + rc.rawlog + ", backend " +
                            rc.mapping.backend + ", cap " +
                            reducers::BudgetOptions::capText(rc.budget.max_landmarks) + ", " +
                            std::to_string(steps.size()) + " steps, " + seedText(rc, request.seeds);
  std::string& md = result.markdown;
  attempt("comparison.md",
          [&] { md = report::writeComparisonMarkdown(top->file("comparison.md"), title, rows); });
  if (request.offline_optimum)
    attempt("offline_optimum.csv", [&] {
      md += writeOfflineOptimumFiles(*top, rc, compared, steps);
      writeFileAtomically(top->file("comparison.md"), md);  // the table with its optimum
    });
  // The figure names the rawlog by its file name: a paper's caption has no room for a path.
  std::string figure_title = title.substr(std::string("budget-slam ").size());
  figure_title.replace(figure_title.find(rc.rawlog), rc.rawlog.size(),
                       std::filesystem::path(rc.rawlog).filename().string());
  attempt("comparison figure", [&] {
    writeComparisonChart(*top, rc.report.figure_title ? figure_title : "", compared, steps,
                         truth.get(), rc.budget.max_landmarks, rc.report.figure_formats);
  });
  RunOutcome summary;
  summary.status = outcome.status, summary.kind = outcome.kind;
  summary.error = outcome.first_error;
  summary.files_not_written = not_written;
  summary.given = {{"started", true},       {"rawlog", rc.rawlog},     {"sidecar_ini", rc.sidecar},
                   {"config", label},       {"runs", compared.size()}, {"seeds", request.seeds},
                   {"steps", steps.size()}, {"threads", threads}};
  if (!top->earlierRun().empty()) summary.given["earlier_run_moved_to"] = top->earlierRun();
  try {
    writeSummary(top->file("summary.json"), summary);
  } catch (const std::exception& e) {
    // Said with the comparison's last line (one line more only when there was none).
    if (outcome.lines.empty()) {
      outcome.add(RunStatus::Failed, ErrorKind::Output, failureLine(e), true);
    } else {
      outcome.lines.back().text = withAlso(outcome.lines.back().text, failureLine(e));
      outcome.status = RunStatus::Failed, outcome.kind = ErrorKind::Output;
    }
  }
  return result;
}

}  // namespace budget_slam::runs
