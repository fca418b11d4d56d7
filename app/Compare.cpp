// budget-slam compare: the rawlog parsed once, the unreduced reference and one run per reducer in
// parallel threads, then every run measured against the reference and the ground truth
// (docs/ARCHITECTURE.md "Data flow", docs/OUTPUTS.md).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "BudgetSlamApp.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Progress.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/metrics/ReferenceMetrics.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/report/ComparisonTable.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/report/RunFiles.h"
#include "budget_slam/runs/BuiltinBackends.h"
#include "budget_slam/runs/Comparison.h"
#include "budget_slam/runs/OfflineOptimum.h"
#include "budget_slam/runs/ProcessProbes.h"
#include "budget_slam/runs/Relocalize.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/RunSpecs.h"
#include "budget_slam/runs/ShadowReducers.h"
#include "budget_slam/runs/SummaryJson.h"

namespace budget_slam::app {
namespace {

using runs::CompareOutcome;
using runs::CompareRun;
using runs::ErrorKind;
using runs::RunDriver;
using runs::RunStatus;
using Runs = runs::CompareRuns;

/// --relocalize: every final map of an ok run (the reference's too) localizes each traversal;
/// fills the reloc_* columns of `rows` and adds the failed localizations to `outcome`.
std::vector<runs::RelocalizationResult> relocalizeMaps(
    const Runs& compared, const std::vector<runs::Traversal>& traversals,
    const std::vector<TrajectoryPoint>* reference, const runs::Request& cli,
    std::vector<report::ComparisonRow>& rows, CompareOutcome& outcome) {
  // One mapped area for every map (the reference run's path, when it ended ok), so that every
  // map is scored on the same steps.
  std::vector<mrpt::math::TPose2D> reference_path;
  if (compared.front()->ok())
    for (const auto& p : compared.front()->driver->backend().trajectory())
      reference_path.push_back(p.pose);
  std::vector<runs::MapOfRun> maps;
  for (const auto& r : compared)
    if (r->ok()) {
      std::vector<mrpt::math::TPose2D> own;
      if (reference_path.empty())
        for (const auto& p : r->driver->backend().trajectory()) own.push_back(p.pose);
      maps.push_back({r->name, r->driver->folder().path(), r->driver->backend().landmarks(),
                      r->driver->mapAlignment(), reference_path.empty() ? own : reference_path});
    }
  auto relocalized = runs::relocalizeAll(maps, traversals, reference, cli.reference_trajectory,
                                         cli.threads, cli.force);
  runs::addRelocalizationColumns(rows, relocalized, runs::kReferenceRun);
  for (const auto& r : relocalized)
    if (r.status != RunStatus::Ok)
      outcome.add(r.status, r.kind,
                  "run '" + r.run + "', --relocalize '" + r.traversal + "': " + r.error, true);
  return relocalized;
}

/// --offline-optimum: offline_optimum.csv; returns its table (for comparison.md).
std::string writeOfflineOptimumFiles(const report::OutputFolder& top, const runs::RunConfig& rc,
                                     const Runs& compared, const std::vector<Step>& steps) {
  if (!rc.budget.max_landmarks) throw InputError("--offline-optimum needs a cap (not --cap none)");
  std::vector<runs::FinalMap> maps;
  for (const auto& r : compared) {
    runs::FinalMap m{r->name, {}};
    for (const auto& l : r->driver->backend().landmarks()) m.kept.push_back(l.id);
    maps.push_back(std::move(m));
  }
  const std::string table = runs::writeOfflineOptimum(
      top.file("offline_optimum.csv"), rc.ini, steps, compared.front()->driver->onlinePoses(), maps,
      *rc.budget.max_landmarks);
  return table;
}

}  // namespace

int BudgetSlamApp::runCompare() {
  std::optional<report::OutputFolder> top;
  Runs compared;
  // A failure before the runs started: one line, the top summary.json and those of the runs made
  // so far say why (and that nothing started: the next compare into the folder replaces them).
  const auto fail = [&](const std::string& why, RunStatus status, ErrorKind kind) {
    const std::string msg = printable(why);  // one line, valid UTF-8 (summary.json)
    std::string not_saved;
    runs::RunOutcome o;
    o.fail(status, kind, msg);
    o.given = {{"started", false}};
    // The runs' summaries say the comparison's status and error (their own line is this one).
    const nlohmann::json given = runs::summaryJson(o);
    if (top) {
      for (const auto& r : compared) {
        try {
          r->driver->finish(status, kind, "the comparison did not start: " + msg, 0, given);
        } catch (const std::exception&) {
          // its line is this failure's line; the top summary says it
        }
      }
      try {
        runs::writeSummary(top->file("summary.json"), o);
      } catch (const std::exception& e) {
        not_saved = failureLine(e);
      }
    }
    *err << "budget-slam: " << (status == RunStatus::Interrupted ? "" : "error: ")
         << withAlso(msg, not_saved) << std::endl;
    return runs::exitCode(status, kind);
  };
  const auto failed = [&](const std::exception& e, const std::string& why) {
    return fail(why, RunStatus::Failed, runs::errorKindOf(e));
  };

  runs::RunConfig rc;
  std::vector<std::string> names = cli_.reducers;
  try {
    loadConfig();
    rc = runs::loadRunConfig(params, cli_, config_label_);
    // --reducers was checked with the command line (BudgetSlamApp::initialize).
    if (names.empty())
      for (const auto& n : reducers::builtinReducers().names())
        if (n != "none") names.push_back(n);
    for (const auto& n : names) runs::checkCapFor(rc, cli_, n, config_label_);
  } catch (const Error& e) {
    if (!cli_.outdir.empty()) try {
        top.emplace(cli_.outdir, cli_.force);
      } catch (const Error&) {
      }
    return failed(e, e.what());
  }
  for (const auto& w : rc.warnings) *err << "budget-slam: warning: " << w << std::endl;
  metrics::MetricsOptions metric_options;
  try {
    metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
    top.emplace(rc.outdir, cli_.force);
  } catch (const Error& e) {
    return failed(e, e.what());
  }
  if (!top->earlierRun().empty() && !cli_.quiet)
    *err << "budget-slam: note: " << top->path() << " held an earlier run; its files were moved to "
         << top->earlierRun() << "/" << std::endl;

  std::shared_ptr<dataset::GroundTruth> truth;
  std::vector<Step> steps;
  std::vector<runs::Traversal> traversals;     // --relocalize
  std::vector<TrajectoryPoint> reference_tum;  // --reference-trajectory
  try {
    Cancellation::check();  // a stop request that came while the program started
    traversals = runs::loadTraversals(params, cli_, config_label_);
    if (!cli_.reference_trajectory.empty())
      reference_tum = report::readTrajectoryTum(cli_.reference_trajectory, 50'000'000);
    writeFileAtomically(top->file("config_used.ini"), rc.ini.getContent());
    truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(
        rc.rawlog, rc.mapping.ground_truth_file, rc.mapping.ground_truth_file_robot));
    ProgressReporter reading(*err, "reading the rawlog", progressSettings(rc.report));
    auto read = runs::readSteps(rc.rawlog, rc.mapping.max_steps, reading);
    if (!read)
      return fail(
          std::string("interrupted by ") + Cancellation::signalName() + " while reading the rawlog",
          RunStatus::Interrupted, ErrorKind::Stopped);
    steps = std::move(*read);
    runs::makeRuns(rc.ini, runs::builtinBackends(), runs::driverSpec(rc), names, cli_.seeds, *top,
                   cli_.force, truth, compared);
  } catch (const Interrupted&) {
    return fail(
        std::string("interrupted by ") + Cancellation::signalName() + " before the first step",
        RunStatus::Interrupted, ErrorKind::Stopped);
  } catch (const Error& e) {
    return failed(e, e.what());
  } catch (const std::exception& e) {
    return failed(e, failureLine(e));
  }

  // One thread a core, each taking whole runs; every run's outputs are written whatever its end.
  const std::size_t wanted = cli_.threads ? cli_.threads : runs::availableCpus();
  const std::size_t threads =
      std::max<std::size_t>(1, std::min<std::size_t>(wanted, compared.size()));
  {
    ProgressReporter progress(*err, "compare", progressSettings(rc.report));
    const std::string fewer = runs::runInThreads(compared, steps, threads, on_end_phase, progress);
    if (!fewer.empty())
      *err << "budget-slam: warning: " << fewer << "; the runs went on in them" << std::endl;
  }

  // Metrics against the reference, then every run's files.
  const CompareRun& ref = *compared.front();
  const std::size_t ref_landmarks = ref.driver->backend().landmarkCount();
  const std::size_t ref_poses = ref.driver->backend().poseCount();
  // Without sensor IDs, a final map's coverage goes through the reference run's association
  // (docs/OUTPUTS.md, "Relocalization coverage").
  if (ref.ok() && runs::withoutLandmarkIds(steps))
    for (const auto& r : compared)
      if (r->ok())
        r->driver->setFinalRelocCoverage(runs::relocCoverageThroughReference(
            *ref.driver, *r->driver, metric_options.reloc_match_chi2));
  std::vector<report::ComparisonRow> rows;
  CompareOutcome outcome;
  for (const auto& r : compared) {
    const nlohmann::json extra = {{"rawlog", rc.rawlog},
                                  {"sidecar_ini", rc.sidecar},
                                  {"config", config_label_},
                                  {"run", r->name}};
    const auto m = runs::finishRun(*r, ref, steps.size(), metric_options.eig_max_rows, extra);
    // The reference's failure fails every comparison, but the others' errors are their own.
    if (!r->ok()) outcome.add(r->status, r->kind, "run '" + r->name + "': " + r->error, false);
    for (const auto& f : r->driver->budget().shadowFailures())
      outcome.lines.push_back("warning: run '" + r->name + "': " + runs::shadowFailureLine(f));
    rows.push_back(runs::comparisonRow(*r, m, ref_landmarks, ref_poses));
  }

  std::vector<runs::RelocalizationResult> relocalized;
  if (!traversals.empty())
    relocalized = relocalizeMaps(compared, traversals,
                                 cli_.reference_trajectory.empty() ? nullptr : &reference_tum, cli_,
                                 rows, outcome);

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
            [&] { runs::writeRelocalizationCsv(top->file("relocalization.csv"), relocalized); });
  std::string seed_text = "seed " + std::to_string(rc.budget.seed);
  if (!cli_.seeds.empty()) {
    const bool range = cli_.seeds.back() - cli_.seeds.front() + 1 == cli_.seeds.size();
    seed_text = cli_.seeds.size() == 1 ? "seed " + std::to_string(cli_.seeds.front())
                : range                ? "seeds " + std::to_string(cli_.seeds.front()) + " to " +
                              std::to_string(cli_.seeds.back())
                        : std::to_string(cli_.seeds.size()) + " seeds";
  }
  const std::string title = "budget-slam compare: " + rc.rawlog + ", backend " +
                            rc.mapping.backend + ", cap " +
                            reducers::BudgetOptions::capText(rc.budget.max_landmarks) + ", " +
                            std::to_string(steps.size()) + " steps, " + seed_text;
  std::string md;
  attempt("comparison.md",
          [&] { md = report::writeComparisonMarkdown(top->file("comparison.md"), title, rows); });
  if (cli_.offline_optimum)
    attempt("offline_optimum.csv", [&] {
      md += writeOfflineOptimumFiles(*top, rc, compared, steps);
      writeFileAtomically(top->file("comparison.md"), md);  // the table with its optimum
    });
  // The figure names the rawlog by its file name: a paper's caption has no room for a path.
  std::string figure_title = title.substr(std::string("budget-slam ").size());
  figure_title.replace(figure_title.find(rc.rawlog), rc.rawlog.size(),
                       std::filesystem::path(rc.rawlog).filename().string());
  attempt("comparison figure", [&] {
    runs::writeComparisonChart(*top, figure_title, compared, steps, truth.get(),
                               rc.budget.max_landmarks, rc.report.figure_formats);
  });
  runs::RunOutcome summary;
  summary.status = outcome.status, summary.kind = outcome.kind;
  summary.error = outcome.first_error;
  summary.files_not_written = not_written;
  summary.given = {{"started", true},           {"rawlog", rc.rawlog},
                   {"sidecar_ini", rc.sidecar}, {"config", config_label_},
                   {"runs", compared.size()},   {"seeds", cli_.seeds},
                   {"steps", steps.size()},     {"threads", threads}};
  if (!top->earlierRun().empty()) summary.given["earlier_run_moved_to"] = top->earlierRun();
  try {
    runs::writeSummary(top->file("summary.json"), summary);
  } catch (const std::exception& e) {
    // Said with the comparison's last line (one line more only when there was none).
    if (outcome.lines.empty()) {
      outcome.add(RunStatus::Failed, ErrorKind::Output, failureLine(e), true);
    } else {
      outcome.lines.back() = withAlso(outcome.lines.back(), failureLine(e));
      outcome.status = RunStatus::Failed, outcome.kind = ErrorKind::Output;
    }
  }
  if (!cli_.quiet && !md.empty()) *out << md << "outputs in " << top->path() << "/\n";
  for (const auto& line : outcome.lines) *err << "budget-slam: " << printable(line) << std::endl;
  if (!stdoutWritten(top->path()) && outcome.status == RunStatus::Ok)
    return runs::exitCode(RunStatus::Failed, ErrorKind::Output);
  return outcome.exitCode();
}

}  // namespace budget_slam::app
