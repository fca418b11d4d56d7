// budget-slam compare: the rawlog parsed once, the unreduced reference and one run per reducer in
// parallel threads, then every run measured against the reference and the ground truth
// (docs/ARCHITECTURE.md "Data flow", docs/OUTPUTS.md).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "BudgetSlamApp.h"
#include "BuiltinBackends.h"
#include "OfflineOptimum.h"
#include "Relocalize.h"
#include "RunConfig.h"
#include "RunSpecs.h"
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
#include "budget_slam/runs/CompareRuns.h"
#include "budget_slam/runs/ProcessProbes.h"
#include "budget_slam/runs/ShadowReducers.h"
#include "budget_slam/runs/SummaryJson.h"

namespace budget_slam::app {
namespace {

using runs::CompareRun;
using runs::ErrorKind;
using runs::RunDriver;
using runs::RunStatus;

constexpr const char* kReference = "reference";

using Runs = std::vector<std::unique_ptr<CompareRun>>;

nlohmann::json toJson(const metrics::ReferenceMetrics& m) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"poses", m.poses},
          {"landmarks", m.landmarks},
          {"ate_m", num(m.ate)},
          {"ale_m", num(m.ale)},
          {"are_deg", num(m.are_deg)},
          {"ud_pct", num(m.ud_percent)},
          {"ud_std_factor", num(m.ud_std_factor)},
          {"eig_min", num(m.eig_min)},
          {"eig_max", num(m.eig_max)},
          {"eig_rows", m.eig_rows}};
}

/// What summary.json holds of a number: a non-finite value is null there, missing in the table.
double finiteOrNaN(double v) {
  return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
}

/// How compare ends: its status (and so its exit code), the first error (its summary.json), and
/// one stderr line a run or localization that did not end ok and a warning a failed shadow
/// reducer.
struct CompareOutcome {
  RunStatus status = RunStatus::Ok;
  ErrorKind kind = ErrorKind::None;
  std::string first_error;
  std::vector<std::string> lines;

  /// A run that ended `s` (failed or interrupted) for the reason `line`. An interrupted run
  /// makes the comparison interrupted unless another failed; with `keep_first`, a status already
  /// set stays.
  void add(RunStatus s, ErrorKind k, const std::string& line, bool keep_first) {
    if (!keep_first || status == RunStatus::Ok) {
      const bool interrupted =
          s == RunStatus::Interrupted && (keep_first || status != RunStatus::Failed);
      status = interrupted ? RunStatus::Interrupted : RunStatus::Failed;
      if (kind == ErrorKind::None || !interrupted) kind = interrupted ? ErrorKind::Stopped : k;
    }
    if (first_error.empty()) first_error = line;
    lines.push_back((s == RunStatus::Interrupted ? "" : "error: ") + line);
  }
  int exitCode() const { return runs::exitCode(status, kind); }
};

/// The rawlog's steps, read once for every driver (at most `limit`, 0 = all); nullopt when a
/// stop request came while reading. Throws InputError when no step has a bearing-range reading.
std::optional<std::vector<Step>> readSteps(const std::string& rawlog, std::size_t limit,
                                           ProgressReporter& reading) {
  std::vector<Step> steps;
  dataset::RawlogReader reader(rawlog);
  reader.setStopCheck([] { return Cancellation::requested(); });
  while (limit == 0 || steps.size() < limit) {
    auto s = reader.next();
    if (s) {
      steps.push_back(std::move(*s));
      reading.update(limit ? double(steps.size()) / double(limit) : reader.progress(), steps.size(),
                     limit, "");
    } else if (!reader.stopped()) {
      break;
    }
    if (Cancellation::requested()) {
      reading.finish(false);
      return std::nullopt;
    }
  }
  reading.finish(true);
  if (reader.bearingRangeSteps() == 0)
    throw InputError("rawlog '" + rawlog + "' holds no CObservationBearingRange");
  return steps;
}

/// The reference run (reducer none) and one run a reducer of `names` (with `seeds`: one a reducer
/// and seed, named <reducer>/seed<S>), each with its folder under `top` and its config_used.ini,
/// appended to `runs` one by one (on an error, the runs made so far are there to say why in their
/// summary.json). The reference drops nothing, so no seed changes it: it runs once.
void makeRuns(const RunConfig& rc, const std::vector<std::string>& names,
              const std::vector<std::uint64_t>& seeds, const report::OutputFolder& top, bool force,
              const std::shared_ptr<dataset::GroundTruth>& truth, Runs& runs) {
  struct Planned {
    std::string name, reducer;
    std::optional<std::uint64_t> seed;
  };
  std::vector<Planned> all = {{kReference, "none", std::nullopt}};
  for (const auto& n : names) {
    if (seeds.empty()) all.push_back({n, n, std::nullopt});
    for (const auto s : seeds) all.push_back({n + "/seed" + std::to_string(s), n, s});
  }
  for (const auto& [name, reducer, seed] : all) {
    auto run = std::make_unique<CompareRun>();
    run->name = name;
    mrpt::config::CConfigFileMemory ini;
    copyIni(rc.ini, ini);  // no second ${...} expansion
    reducers::BudgetOptions budget = rc.budget;
    budget.reducer = reducer;
    ini.write(reducers::BudgetOptions::kSection, "reducer", budget.reducer);
    if (seed) {
      budget.seed = *seed;
      ini.write(reducers::BudgetOptions::kSection, "seed", std::to_string(*seed));
    }
    report::OutputFolder folder(top.file(name), force);
    writeFileAtomically(folder.file("config_used.ini"), ini.getContent());
    runs::DriverSpec spec = driverSpec(rc);
    spec.budget = budget;
    spec.keep_history = true;  // the comparison's figures need every run's history
    run->driver = std::make_unique<RunDriver>(ini, builtinBackends(), spec, folder, truth);
    runs.push_back(std::move(run));
  }
}

/// Ends run `r`: its metrics against the reference (when both are ok) and its outputs
/// (RunDriver::finish, with `extra` in summary.json). A run whose outputs could not be written,
/// or whose estimate is not finite, becomes failed.
metrics::ReferenceMetrics finishRun(CompareRun& r, const CompareRun& ref, std::size_t steps,
                                    std::size_t eig_max_rows, nlohmann::json extra) {
  metrics::ReferenceMetrics m;
  // A stop request after a run's end phase: its outputs are still written (quickly), marked.
  if (r.ok() && Cancellation::requested()) {
    r.status = RunStatus::Interrupted, r.kind = ErrorKind::Stopped;
    r.error = runs::interruptedLine(r, " before its outputs were written,");
  }
  if (ref.ok() && r.ok()) {
    m = metrics::compareWithReference(ref.driver->backend(), r.driver->backend(), eig_max_rows);
    extra["reference_metrics"] = toJson(m);
  }
  try {
    r.result = r.driver->finish(r.status, r.kind, r.error, steps, extra);
    if (r.ok() && !r.result->ok()) {
      // An output of the run could not be written (a full disk), or its estimate diverged.
      r.status = RunStatus::Failed, r.kind = r.result->kind;
      r.error = r.result->error;
    }
  } catch (const std::exception& e) {
    r.status = RunStatus::Failed, r.kind = ErrorKind::Output;
    r.error = std::string("while saving outputs: ") + exceptionLine(e);
  }
  return m;
}

/// comparison.csv's row of run `r` (docs/OUTPUTS.md), with `m` its metrics against the
/// reference, which holds `ref_landmarks` landmarks and `ref_poses` poses.
report::ComparisonRow comparisonRow(const CompareRun& r, const metrics::ReferenceMetrics& m,
                                    std::size_t ref_landmarks, std::size_t ref_poses) {
  const RunDriver& p = *r.driver;
  report::ComparisonRow row;
  row.run = r.name;
  row.reducer = p.budget().options().reducer;
  row.backend = p.backend().name();
  row.status = runs::statusName(r.status);
  row.cap = p.budget().capped() ? static_cast<long long>(*p.budget().options().max_landmarks) : -1;
  row.seed = static_cast<long long>(p.budget().options().seed);
  row.landmarks = p.backend().landmarkCount();
  row.poses = p.backend().poseCount();
  if (ref_landmarks)
    row.landmarks_reduction_pct = 100.0 * (1.0 - double(row.landmarks) / double(ref_landmarks));
  if (ref_poses) row.poses_reduction_pct = 100.0 * (1.0 - double(row.poses) / double(ref_poses));
  row.evictions = p.evictions();
  row.refused = p.refused();
  row.ref_ate_m = m.ate, row.ref_ale_m = m.ale, row.ref_are_deg = m.are_deg;
  row.ref_ud_pct = m.ud_percent, row.ref_ud_std_factor = m.ud_std_factor;
  row.ref_eig_min = m.eig_min, row.ref_eig_max = m.eig_max;
  if (r.result && r.result->ground_truth) {
    // The numbers of the run's summary.json (metrics::groundTruthErrors), not a second computation.
    const metrics::GroundTruthErrors& gt = r.result->ground_truth->errors;
    row.gt_trajectory_rmse_aligned_m = finiteOrNaN(gt.trajectory_rmse_aligned);
    row.gt_trajectory_rpe_10m_m = finiteOrNaN(gt.rpe.rmse);
    row.gt_trajectory_rmse_m = finiteOrNaN(gt.trajectory_rmse);
    row.gt_trajectory_max_m = finiteOrNaN(gt.trajectory_max);
    row.gt_landmark_rmse_m = finiteOrNaN(gt.landmark_rmse);
    row.gt_landmark_rmse_aligned_m = finiteOrNaN(gt.landmark_rmse_aligned);
    row.nees_mean = finiteOrNaN(r.result->ground_truth->nees.mean);
  }
  row.time_s = p.totalStepSeconds();
  if (r.result && r.result->run) {
    const metrics::RelocalizationCoverage& reloc = r.result->run->relocalization.coverage;
    row.reloc_coverage_pct = finiteOrNaN(reloc.coverage_pct);
    row.reloc_mean_landmarks = finiteOrNaN(reloc.mean_landmarks);
  }
  return row;
}

/// --relocalize: every final map of an ok run (the reference's too) localizes each traversal;
/// fills the reloc_* columns of `rows` and adds the failed localizations to `outcome`.
std::vector<RelocalizationResult> relocalizeMaps(const Runs& runs,
                                                 const std::vector<Traversal>& traversals,
                                                 const std::vector<TrajectoryPoint>* reference,
                                                 const CommandLine& cli,
                                                 std::vector<report::ComparisonRow>& rows,
                                                 CompareOutcome& outcome) {
  // One mapped area for every map (the reference run's path, when it ended ok), so that every
  // map is scored on the same steps.
  std::vector<mrpt::math::TPose2D> reference_path;
  if (runs.front()->ok())
    for (const auto& p : runs.front()->driver->backend().trajectory())
      reference_path.push_back(p.pose);
  std::vector<MapOfRun> maps;
  for (const auto& r : runs)
    if (r->ok()) {
      std::vector<mrpt::math::TPose2D> own;
      if (reference_path.empty())
        for (const auto& p : r->driver->backend().trajectory()) own.push_back(p.pose);
      maps.push_back({r->name, r->driver->folder().path(), r->driver->backend().landmarks(),
                      r->driver->mapAlignment(), reference_path.empty() ? own : reference_path});
    }
  auto relocalized =
      relocalizeAll(maps, traversals, reference, cli.reference_trajectory, cli.threads, cli.force);
  addRelocalizationColumns(rows, relocalized, kReference);
  for (const auto& r : relocalized)
    if (r.status != runs::statusName(RunStatus::Ok)) {
      const bool interrupted = r.status == runs::statusName(RunStatus::Interrupted);
      outcome.add(interrupted ? RunStatus::Interrupted : RunStatus::Failed,
                  interrupted ? ErrorKind::Stopped : ErrorKind::Input,
                  "run '" + r.run + "', --relocalize '" + r.traversal + "': " + r.error, true);
    }
  return relocalized;
}

/// Position error over the steps of each run, against `truth` rows or the reference run.
std::vector<report::Series> errorSeries(const Runs& runs, const dataset::GroundTruth* truth,
                                        std::size_t steps) {
  std::vector<report::Series> out;
  const auto* ref = runs.front()->driver.get();
  for (const auto& r : runs) {
    if (!truth && r->name == kReference) continue;
    report::Series s;
    s.name = r->name;
    const auto& online = r->driver->onlinePoses();
    for (std::size_t k = 0; k < online.size(); ++k) {
      const auto& p = online[k].estimate.mean;
      double e;
      if (truth) {
        const std::size_t row = metrics::groundTruthRow(online[k].step, truth->path.size(), steps);
        if (row >= truth->path.size()) continue;
        e = std::hypot(p.x - truth->path[row].x, p.y - truth->path[row].y);
      } else {
        if (k >= ref->onlinePoses().size()) break;
        const auto& q = ref->onlinePoses()[k].estimate.mean;
        e = std::hypot(p.x - q.x, p.y - q.y);
      }
      s.x.push_back(static_cast<double>(online[k].step));
      s.y.push_back(e);
    }
    out.push_back(std::move(s));
  }
  return out;
}

/// comparison.<png|pdf|svg>: the landmark count over the steps (the cap marked), and the robot
/// position error against ground truth (else the difference to the reference run); the
/// reference dashed black.
void writeComparisonChart(const report::OutputFolder& top, const std::string& title,
                          const Runs& runs, const std::vector<Step>& steps,
                          const dataset::GroundTruth* truth, const RunConfig& rc) {
  std::vector<report::ChartPanel> panels;
  report::ChartPanel count{"landmarks in the map", "step", "landmarks", {}, false, {}, true};
  if (rc.budget.max_landmarks)
    count.marks.push_back(
        {double(*rc.budget.max_landmarks), "cap " + std::to_string(*rc.budget.max_landmarks)});
  for (const auto& r : runs) {
    report::Series s{r->name, {}, {}, r->name == kReference};
    const auto& counts = r->driver->landmarkCounts();
    for (std::size_t k = 0; k < counts.size(); ++k)
      s.x.push_back(double(steps[k].index)), s.y.push_back(double(counts[k]));
    count.series.push_back(std::move(s));
  }
  panels.push_back(std::move(count));
  const bool has_path = truth && !truth->path.empty();
  const auto gt = has_path ? metrics::toEstimateFrame(*truth) : dataset::GroundTruth();
  panels.push_back({has_path ? "robot position error against ground truth (online estimate)"
                             : "robot position difference to the reference run (online estimate)",
                    "step",
                    "m",
                    errorSeries(runs, has_path ? &gt : nullptr, steps.size()),
                    false,
                    {}});
  for (auto& s : panels.back().series) s.reference = s.name == kReference;
  for (const auto format : rc.report.figure_formats)
    report::writeChart(top.file(report::figureFile("comparison", format)), title, panels, format);
}

/// --offline-optimum: offline_optimum.csv; returns its table (for comparison.md).
std::string writeOfflineOptimumFiles(const report::OutputFolder& top, const RunConfig& rc,
                                     const Runs& runs, const std::vector<Step>& steps) {
  if (!rc.budget.max_landmarks) throw InputError("--offline-optimum needs a cap (not --cap none)");
  std::vector<FinalMap> maps;
  for (const auto& r : runs) {
    FinalMap m{r->name, {}};
    for (const auto& l : r->driver->backend().landmarks()) m.kept.push_back(l.id);
    maps.push_back(std::move(m));
  }
  const std::string table =
      writeOfflineOptimum(top.file("offline_optimum.csv"), rc.ini, steps,
                          runs.front()->driver->onlinePoses(), maps, *rc.budget.max_landmarks);
  return table;
}

}  // namespace

int BudgetSlamApp::runCompare() {
  std::optional<report::OutputFolder> top;
  Runs runs;
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
      for (const auto& r : runs) {
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

  RunConfig rc;
  std::vector<std::string> names = cli_.reducers;
  try {
    loadConfig();
    rc = loadRunConfig(params, cli_, config_label_);
    // --reducers was checked with the command line (BudgetSlamApp::initialize).
    if (names.empty())
      for (const auto& n : reducers::builtinReducers().names())
        if (n != "none") names.push_back(n);
    for (const auto& n : names) checkCapFor(rc, cli_, n, config_label_);
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
  std::vector<Traversal> traversals;           // --relocalize
  std::vector<TrajectoryPoint> reference_tum;  // --reference-trajectory
  try {
    Cancellation::check();  // a stop request that came while the program started
    traversals = loadTraversals(params, cli_, config_label_);
    if (!cli_.reference_trajectory.empty())
      reference_tum = report::readTrajectoryTum(cli_.reference_trajectory, 50'000'000);
    writeFileAtomically(top->file("config_used.ini"), rc.ini.getContent());
    truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(
        rc.rawlog, rc.mapping.ground_truth_file, rc.mapping.ground_truth_file_robot));
    ProgressReporter reading(*err, "reading the rawlog", progressSettings(rc.report));
    auto read = readSteps(rc.rawlog, rc.mapping.max_steps, reading);
    if (!read)
      return fail(
          std::string("interrupted by ") + Cancellation::signalName() + " while reading the rawlog",
          RunStatus::Interrupted, ErrorKind::Stopped);
    steps = std::move(*read);
    makeRuns(rc, names, cli_.seeds, *top, cli_.force, truth, runs);
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
  const std::size_t threads = std::max<std::size_t>(1, std::min<std::size_t>(wanted, runs.size()));
  {
    ProgressReporter progress(*err, "compare", progressSettings(rc.report));
    const std::string fewer = runs::runInThreads(runs, steps, threads, on_end_phase, progress);
    if (!fewer.empty())
      *err << "budget-slam: warning: " << fewer << "; the runs went on in them" << std::endl;
  }

  // Metrics against the reference, then every run's files.
  const CompareRun& ref = *runs.front();
  const std::size_t ref_landmarks = ref.driver->backend().landmarkCount();
  const std::size_t ref_poses = ref.driver->backend().poseCount();
  // Without sensor IDs, a final map's coverage goes through the reference run's association
  // (docs/OUTPUTS.md, "Relocalization coverage").
  if (ref.ok() && runs::withoutLandmarkIds(steps))
    for (const auto& r : runs)
      if (r->ok())
        r->driver->setFinalRelocCoverage(runs::relocCoverageThroughReference(
            *ref.driver, *r->driver, metric_options.reloc_match_chi2));
  std::vector<report::ComparisonRow> rows;
  CompareOutcome outcome;
  for (const auto& r : runs) {
    const nlohmann::json extra = {{"rawlog", rc.rawlog},
                                  {"sidecar_ini", rc.sidecar},
                                  {"config", config_label_},
                                  {"run", r->name}};
    const auto m = finishRun(*r, ref, steps.size(), metric_options.eig_max_rows, extra);
    // The reference's failure fails every comparison, but the others' errors are their own.
    if (!r->ok()) outcome.add(r->status, r->kind, "run '" + r->name + "': " + r->error, false);
    for (const auto& f : r->driver->budget().shadowFailures())
      outcome.lines.push_back("warning: run '" + r->name + "': " + runs::shadowFailureLine(f));
    rows.push_back(comparisonRow(*r, m, ref_landmarks, ref_poses));
  }

  std::vector<RelocalizationResult> relocalized;
  if (!traversals.empty())
    relocalized = relocalizeMaps(runs, traversals,
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
            [&] { writeRelocalizationCsv(top->file("relocalization.csv"), relocalized); });
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
      md += writeOfflineOptimumFiles(*top, rc, runs, steps);
      writeFileAtomically(top->file("comparison.md"), md);  // the table with its optimum
    });
  // The figure names the rawlog by its file name: a paper's caption has no room for a path.
  std::string figure_title = title.substr(std::string("budget-slam ").size());
  figure_title.replace(figure_title.find(rc.rawlog), rc.rawlog.size(),
                       std::filesystem::path(rc.rawlog).filename().string());
  attempt("comparison figure",
          [&] { writeComparisonChart(*top, figure_title, runs, steps, truth.get(), rc); });
  runs::RunOutcome summary;
  summary.status = outcome.status, summary.kind = outcome.kind;
  summary.error = outcome.first_error;
  summary.files_not_written = not_written;
  summary.given = {{"started", true},         {"rawlog", rc.rawlog}, {"sidecar_ini", rc.sidecar},
                   {"config", config_label_}, {"runs", runs.size()}, {"seeds", cli_.seeds},
                   {"steps", steps.size()},   {"threads", threads}};
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
