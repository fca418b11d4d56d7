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
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/engine/OfflineOptimum.h"
#include "budget_slam/engine/ProcessProbes.h"
#include "budget_slam/engine/RawlogSteps.h"
#include "budget_slam/engine/RunLife.h"
#include "budget_slam/engine/ShadowReducers.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/localization/Relocalize.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/Instruments.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/report/RunFiles.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/Comparison.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/RunSpecs.h"

namespace budget_slam::runs {
namespace {

/// Reads every --relocalize rawlog with `cli`'s flags and `params` (errors name the file).
std::vector<Traversal> loadTraversals(const mrpt::config::CConfigFileMemory& params,
                                      const CompareRequest& cli, const std::string& config_label) {
  std::vector<Traversal> out;
  for (const auto& path : cli.relocalize) {
    Traversal t;
    RequestCommon common = cli.common;
    common.rawlog = path;
    RunConfig rc = loadRunConfig(params, common, configFlags(cli), config_label);
    t.name = std::filesystem::path(path).stem().string();
    for (const auto& other : out)
      if (other.name == t.name)
        throw ConfigError("--relocalize: two traversals are named '" + t.name + "'");
    t.rawlog = rc.rawlog;
    t.config_used = configUsed(rc.ini);
    t.localization = rc.localization;
    t.ini = std::move(rc.ini);
    t.truth = dataset::loadGroundTruth(t.rawlog, rc.mapping.ground_truth_file,
                                       rc.mapping.ground_truth_file_robot);
    auto steps = readRawlogSteps(t.rawlog, 0, nullptr);
    if (!steps) throw Error("interrupted while reading '" + path + "'");
    t.steps = std::move(*steps);
    t.steps_in_rawlog = t.steps.size();
    if (t.localization.max_steps && t.steps.size() > t.localization.max_steps)
      t.steps.resize(t.localization.max_steps);
    out.push_back(std::move(t));
  }
  return out;
}

/// --relocalize: every final map of an ok run (the reference's too) localizes each traversal;
/// fills the reloc_* columns of `rows` and adds the failed localizations to `outcome`.
std::vector<RelocalizationResult> relocalizeMaps(
    const CompareRuns& compared, const std::vector<Traversal>& traversals,
    const std::vector<TrajectoryPoint>* reference, const CompareRequest& request,
    std::vector<report::ComparisonRow>& rows, CompareOutcome& outcome, ProgressReporter& progress) {
  // One mapped area for every map (the reference run's path, when it ended ok), so that every
  // map is scored on the same steps.
  std::vector<Pose2> reference_path;
  if (compared.front()->ok())
    for (const auto& p : compared.front()->driver->backend().trajectory())
      reference_path.push_back(p.pose);
  std::vector<MapOfRun> maps;
  for (const auto& r : compared)
    if (r->ok()) {
      std::vector<Pose2> own;
      if (reference_path.empty())
        for (const auto& p : r->driver->backend().trajectory()) own.push_back(p.pose);
      maps.push_back({r->name, r->driver->folder().path(), r->driver->backend().landmarks(),
                      r->driver->mapAlignment(), reference_path.empty() ? own : reference_path});
    }
  auto relocalized = relocalizeAll(maps, traversals, reference, request.reference_trajectory,
                                   request.threads, request.common.force, &progress);
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

/// What a run that did not start was given: that it did not.
RunGiven notStarted() {
  RunGiven g;
  g.started = false;
  return g;
}

/// "seed 1", "seeds 1 to 5" or "3 seeds" (comparison.md's title).
std::string seedText(const RunConfig& rc, const std::vector<std::uint64_t>& seeds) {
  if (seeds.empty()) return "seed " + std::to_string(rc.budget.seed);
  const bool range = seeds.back() - seeds.front() + 1 == seeds.size();
  return seeds.size() == 1 ? "seed " + std::to_string(seeds.front())
         : range ? "seeds " + std::to_string(seeds.front()) + " to " + std::to_string(seeds.back())
                 : std::to_string(seeds.size()) + " seeds";
}

/// What a comparison runs on, read before its runs start.
struct CompareInputs {
  RunConfig rc;
  std::vector<std::string> names;  ///< the reducers compared (the reference left out)
  metrics::MetricsOptions metric_options;
  std::shared_ptr<dataset::GroundTruth> truth;
  std::vector<Step> steps;
  std::vector<Traversal> traversals;           ///< --relocalize
  std::vector<TrajectoryPoint> reference_tum;  ///< --reference-trajectory
  ProgressSettings progress;                   ///< with the merged ini's interval
};

/// A comparison that ended before its runs started: the life's end as the comparison's outcome.
CompareReport endedBefore(CompareReport result, const RunLife& life, RunLife::End end) {
  CompareOutcome& outcome = result.outcome;
  outcome.status = end.outcome.status, outcome.kind = end.outcome.kind;
  outcome.first_error = end.outcome.error;
  outcome.lines = {{end.outcome.status == RunStatus::Interrupted ? CompareLine::Kind::Interrupted
                                                                 : CompareLine::Kind::Error,
                    end.line}};
  result.folder = life.path();
  result.summary = end.outcome;
  return result;
}

/// The configuration, the output folder, the traversals, config_used.ini, the ground truth, the
/// rawlog read once and the runs made; the end of a comparison that could not start, or nullopt.
std::optional<RunLife::End> setUp(const CompareRequest& request, RequestContext& context,
                                  const RunHooks& hooks, std::ostream& progress_out, RunLife& life,
                                  CompareRuns& compared, CompareInputs& in) {
  const std::string& label = context.config_label;
  try {
    in.rc = loadRunConfig(request, context);
    in.names = request.reducers;
    // --reducers was checked with the request (checkRequest).
    if (in.names.empty())
      for (const auto& n : reducers::builtinReducers().names())
        if (n != "none" && !reducers::isInstrument(n)) in.names.push_back(n);
    for (const auto& n : in.names) checkCapFor(in.rc, request.cap, n, label);
  } catch (const Error& e) {
    life.openToSayWhy(request.common.outdir, request.common.force);
    return life.end(e.what(), RunStatus::Failed, errorKindOf(e));
  }
  const RunConfig& rc = in.rc;
  for (const auto& w : rc.warnings)
    if (hooks.warning) hooks.warning(w);
  in.progress = hooks.progress;
  in.progress.line_every_s = rc.report.progress_every_s;
  try {
    in.metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
    life.open(rc.outdir, request.common.force);
  } catch (const Error& e) {
    return life.end(e.what(), RunStatus::Failed, errorKindOf(e));
  }
  // Each run made so far says its own end: it did not start, and why (issue 35: they carried
  // another run's error as their own); the top summary.json follows.
  life.setFinisher([&](RunOutcome& o) {
    for (const auto& r : compared) {
      try {
        r->driver->finish(o.status, o.kind, "the comparison did not start: " + o.error, 0,
                          notStarted());
      } catch (const std::exception&) {
        // its line is this failure's line; the top summary says it
      }
    }
    return life.writeSummaryHere(o);
  });
  if (const std::string note = life.earlierRunNote(); !note.empty() && hooks.note) hooks.note(note);
  try {
    Cancellation::check();  // a stop request that came while the program started
    in.traversals = loadTraversals(context.params, request, label);
    if (!request.reference_trajectory.empty())
      in.reference_tum = report::readTrajectoryTum(request.reference_trajectory, 50'000'000);
    writeFileAtomically(life.folder().file("config_used.ini"), configUsed(rc.ini));
    in.truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(
        rc.rawlog, rc.mapping.ground_truth_file, rc.mapping.ground_truth_file_robot));
    ProgressReporter reading(progress_out, "reading the rawlog", in.progress);
    auto read = readRawlogSteps(rc.rawlog, rc.mapping.max_steps, &reading);
    if (!read) return life.endInterrupted(" while reading the rawlog");
    in.steps = std::move(*read);
    makeRuns(rc.ini, builtinBackends(), driverSpec(rc), in.names, request.seeds, life.folder(),
             request.common.force, in.truth, compared);
  } catch (const Interrupted&) {
    return life.endInterrupted(" before the first step");
  } catch (const Error& e) {
    return life.end(e.what(), RunStatus::Failed, errorKindOf(e));
  } catch (const std::exception& e) {
    return life.endOn(e);
  }
  return std::nullopt;
}

/// Every run in threads, one a core (at most request.threads), each taking whole runs; returns
/// the threads used.
std::size_t runAll(const CompareRequest& request, const RunHooks& hooks, std::ostream& progress_out,
                   const CompareInputs& in, CompareRuns& compared) {
  const std::size_t wanted = request.threads ? request.threads : availableCpus();
  const std::size_t threads =
      std::max<std::size_t>(1, std::min<std::size_t>(wanted, compared.size()));
  if (const std::string note =
          largeReferenceNote(in.rc.mapping.backend, distinctLandmarkIds(in.steps));
      !note.empty() && hooks.note)
    hooks.note(note);
  std::size_t traversal_steps = 0;
  for (const auto& t : in.traversals) traversal_steps += t.steps.size();
  // Said with the runs' ETA, which does not cover it (its own progress follows).
  const std::string after = in.traversals.empty()
                                ? ""
                                : "then relocalization: " + std::to_string(compared.size()) +
                                      " maps on " + std::to_string(traversal_steps) + " steps";
  ProgressReporter progress(progress_out, "compare", in.progress);
  const std::string fewer =
      runInThreads(compared, in.steps, threads, hooks.on_end_phase, progress, after);
  if (!fewer.empty() && hooks.warning) hooks.warning(fewer + "; the runs went on in them");
  return threads;
}

/// Every run measured against the reference and ended (its files), into `result`'s rows, runs and
/// outcome.
void measureRuns(const CompareInputs& in, const std::string& label, CompareRuns& compared,
                 CompareReport& result) {
  const CompareRun& ref = *compared.front();
  const std::size_t ref_landmarks = ref.driver->backend().landmarkCount();
  const std::size_t ref_poses = ref.driver->backend().poseCount();
  // Without sensor IDs, a final map's coverage goes through the reference run's association
  // (docs/OUTPUTS.md, "Relocalization coverage").
  if (ref.ok() && withoutLandmarkIds(in.steps))
    for (const auto& r : compared)
      if (r->ok())
        r->driver->setFinalRelocCoverage(relocCoverageThroughReference(
            *ref.driver, *r->driver, in.metric_options.reloc_match_chi2));
  for (const auto& r : compared) {
    RunGiven given;
    given.rawlog = in.rc.rawlog, given.sidecar_ini = in.rc.sidecar, given.config = label;
    given.run = r->name;
    const auto m = finishRun(*r, ref, in.steps.size(), in.metric_options.eig_max_rows, given);
    result.runs.push_back({r->name, r->result});
    // The reference's failure fails every comparison, but the others' errors are their own.
    if (!r->ok())
      result.outcome.add(r->status, r->kind, "run '" + r->name + "': " + r->error, false);
    for (const auto& f : r->driver->budget().shadowFailures())
      result.outcome.lines.push_back(
          {CompareLine::Kind::Warning, "run '" + r->name + "': " + shadowFailureLine(f)});
    result.rows.push_back(comparisonRow(*r, m, ref_landmarks, ref_poses));
  }
}

/// comparison.csv, relocalization.csv, comparison.md, offline_optimum.csv and the figure, each
/// attempted: the first that cannot be written (a full disk) fails the comparison in one line.
/// Returns the files not written.
std::vector<std::string> writeComparisonFiles(const CompareRequest& request,
                                              const CompareInputs& in,
                                              const report::OutputFolder& top,
                                              const CompareRuns& compared,
                                              const std::vector<RelocalizationResult>& relocalized,
                                              CompareReport& result) {
  const RunConfig& rc = in.rc;
  std::vector<std::string> not_written;
  const auto attempt = [&](const std::string& name, const std::function<void()>& write) {
    try {
      write();
    } catch (const std::exception& e) {
      if (not_written.empty())
        result.outcome.add(RunStatus::Failed, ErrorKind::Output, report::outputFailureLine(e),
                           true);
      not_written.push_back(name);
    }
  };
  const auto& rows = result.rows;
  attempt("comparison.csv", [&] { report::writeComparisonCsv(top.file("comparison.csv"), rows); });
  if (!in.traversals.empty())
    attempt("relocalization.csv",
            [&] { writeRelocalizationCsv(top.file("relocalization.csv"), relocalized); });
  const std::string title =
      "budget-slam compare: " + rc.rawlog + ", backend " + rc.mapping.backend + ", cap " +
      reducers::BudgetOptions::capText(rc.budget.max_landmarks) + ", " +
      std::to_string(in.steps.size()) + " steps, " + seedText(rc, request.seeds);
  std::string& md = result.markdown;
  attempt("comparison.md",
          [&] { md = report::writeComparisonMarkdown(top.file("comparison.md"), title, rows); });
  if (request.offline_optimum)
    attempt("offline_optimum.csv", [&] {
      md += writeOfflineOptimumFiles(top, rc, compared, in.steps);
      writeFileAtomically(top.file("comparison.md"), md);  // the table with its optimum
    });
  // The figure names the rawlog by its file name: a paper's caption has no room for a path.
  std::string figure_title = title.substr(std::string("budget-slam ").size());
  figure_title.replace(figure_title.find(rc.rawlog), rc.rawlog.size(),
                       std::filesystem::path(rc.rawlog).filename().string());
  attempt("comparison figure", [&] {
    writeComparisonChart(top, rc.report.figure_title ? figure_title : "", compared, in.steps,
                         in.truth.get(), rc.budget.max_landmarks, rc.report.figure_formats);
  });
  return not_written;
}

}  // namespace

CompareReport compare(const CompareRequest& request, RequestContext context,
                      const RunHooks& hooks) {
  CompareReport result;
  RunLife life;
  CompareRuns compared;
  CompareInputs in;
  std::ostringstream no_progress;
  std::ostream& progress_out = hooks.progress_out ? *hooks.progress_out : no_progress;
  if (auto end = setUp(request, context, hooks, progress_out, life, compared, in))
    return endedBefore(std::move(result), life, std::move(*end));
  result.folder = life.path();
  result.started = true;
  const std::size_t threads = runAll(request, hooks, progress_out, in, compared);
  measureRuns(in, context.config_label, compared, result);

  std::vector<RelocalizationResult> relocalized;
  if (!in.traversals.empty()) {
    ProgressReporter progress(progress_out, "relocalize", in.progress);
    relocalized = relocalizeMaps(compared, in.traversals,
                                 request.reference_trajectory.empty() ? nullptr : &in.reference_tum,
                                 request, result.rows, result.outcome, progress);
  }
  // Every output is attempted; summary.json, written last, says which were not.
  RunOutcome summary;
  summary.files_not_written =
      writeComparisonFiles(request, in, life.folder(), compared, relocalized, result);
  CompareOutcome& outcome = result.outcome;
  summary.status = outcome.status, summary.kind = outcome.kind;
  summary.error = outcome.first_error;
  const RunConfig& rc = in.rc;
  RunGiven& given = life.given();
  given.started = true, given.rawlog = rc.rawlog, given.sidecar_ini = rc.sidecar;
  given.config = context.config_label, given.runs = compared.size(), given.seeds = request.seeds;
  given.steps = in.steps.size(), given.threads = threads;
  summary.given = given;
  result.summary = summary;
  if (const std::string not_saved = life.writeSummaryHere(summary); !not_saved.empty()) {
    // Said with the comparison's last line (one line more only when there was none).
    if (outcome.lines.empty()) {
      outcome.add(RunStatus::Failed, ErrorKind::Output, not_saved, true);
    } else {
      outcome.lines.back().text = withAlso(outcome.lines.back().text, not_saved);
      outcome.status = RunStatus::Failed, outcome.kind = ErrorKind::Output;
    }
  }
  return result;
}

}  // namespace budget_slam::runs
