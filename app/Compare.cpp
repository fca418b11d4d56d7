// budget-slam compare: the rawlog parsed once, the unreduced reference and one run per reducer in
// parallel threads, then every run measured against the reference and the ground truth
// (docs/ARCHITECTURE.md "Data flow", docs/OUTPUTS.md).
#include <algorithm>
#include <atomic>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include "BudgetSlamApp.h"
#include "Interrupt.h"
#include "OfflineOptimum.h"
#include "Pipeline.h"
#include "ProgressBar.h"
#include "Relocalize.h"
#include "RunConfig.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/metrics/ReferenceMetrics.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/report/ComparisonTable.h"
#include "budget_slam/report/FileWrite.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFileReaders.h"
#include "budget_slam/report/RunFiles.h"

namespace budget_slam::app {
namespace {

constexpr const char* kReference = "reference";

/// One pipeline of the comparison and how it ended.
struct CompareRun {
  std::string name;
  std::unique_ptr<Pipeline> pipeline;
  std::atomic<std::size_t> steps_done{0};
  std::string status = "ok", error;
};

nlohmann::json toJson(const metrics::ReferenceMetrics& m) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"poses", m.poses},          {"landmarks", m.landmarks},  {"ate_m", num(m.ate)},
          {"ale_m", num(m.ale)},       {"are_deg", num(m.are_deg)}, {"ud_pct", num(m.ud_percent)},
          {"eig_min", num(m.eig_min)}, {"eig_max", num(m.eig_max)}, {"eig_rows", m.eig_rows}};
}

double jsonNumber(const nlohmann::json& j, const char* a, const char* b) {
  if (!j.contains(a) || !j[a].contains(b) || !j[a][b].is_number())
    return std::numeric_limits<double>::quiet_NaN();
  return j[a][b].get<double>();
}

/// Position error over the steps of each run, against `truth` rows or the reference run.
std::vector<report::Series> errorSeries(const std::vector<std::unique_ptr<CompareRun>>& runs,
                                        const dataset::GroundTruth* truth, std::size_t steps) {
  std::vector<report::Series> out;
  const auto* ref = runs.front()->pipeline.get();
  for (const auto& r : runs) {
    if (!truth && r->name == kReference) continue;
    report::Series s;
    s.name = r->name;
    const auto& online = r->pipeline->onlinePoses();
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

}  // namespace

int BudgetSlamApp::runCompare() {
  std::optional<report::OutputFolder> top;
  const auto fail = [&](const std::string& why) {
    const std::string msg = printable(why);  // one line, valid UTF-8 (summary.json)
    *err << "budget-slam: error: " << msg << std::endl;
    if (top) {
      try {
        report::writeJson(top->file("summary.json"), {{"status", "failed"}, {"error", msg}});
      } catch (const std::exception& e) {
        *err << "budget-slam: error: while saving outputs: " << exceptionLine(e) << std::endl;
      }
    }
    return 1;
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
    return fail(e.what());
  }
  metrics::MetricsOptions metric_options;
  try {
    metric_options.loadFromConfigFile(rc.ini, metrics::MetricsOptions::kSection);
    top.emplace(rc.outdir, cli_.force);
  } catch (const Error& e) {
    return fail(e.what());
  }
  if (!top->earlierRun().empty() && !cli_.quiet)
    *err << "budget-slam: note: " << top->path() << " held an earlier run; its files were moved to "
         << top->earlierRun() << "/" << std::endl;

  std::vector<std::unique_ptr<CompareRun>> runs;
  std::shared_ptr<dataset::GroundTruth> truth;
  std::vector<Step> steps;
  std::vector<Traversal> traversals;           // --relocalize
  std::vector<TrajectoryPoint> reference_tum;  // --reference-trajectory
  try {
    traversals = loadTraversals(params, cli_, config_label_);
    if (!cli_.reference_trajectory.empty())
      reference_tum = report::readTrajectoryTum(cli_.reference_trajectory, 50'000'000);
    report::writeFileAtomically(top->file("config_used.ini"), rc.ini.getContent());
    truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(
        rc.rawlog, rc.mapping.ground_truth_file, rc.mapping.ground_truth_file_robot));

    // The rawlog is parsed once; every pipeline reads the same steps.
    dataset::RawlogReader reader(rc.rawlog);
    reader.setStopCheck([] { return InterruptGuard::requested(); });
    ProgressBar reading(*err, !cli_.quiet && err == &std::cerr && stderrIsTerminal());
    const std::size_t limit = rc.mapping.max_steps;
    while (limit == 0 || steps.size() < limit) {
      auto s = reader.next();
      if (s) {
        steps.push_back(std::move(*s));
        reading.update(reader.progress(), "reading step " + std::to_string(steps.size()));
      } else if (!reader.stopped()) {
        break;
      }
      if (InterruptGuard::requested()) {
        reading.done();
        *err << "budget-slam: interrupted by " << InterruptGuard::what()
             << " while reading the rawlog" << std::endl;
        report::writeJson(top->file("summary.json"),
                          {{"status", "interrupted"}, {"error", "interrupted while reading"}});
        return 130;
      }
    }
    reading.done();
    if (reader.bearingRangeSteps() == 0)
      throw InputError("rawlog '" + rc.rawlog + "' holds no CObservationBearingRange");

    std::vector<std::string> all = {kReference};
    all.insert(all.end(), names.begin(), names.end());
    for (const auto& name : all) {
      auto run = std::make_unique<CompareRun>();
      run->name = name;
      mrpt::config::CConfigFileMemory ini;
      copyIni(rc.ini, ini);  // no second ${...} expansion
      reducers::BudgetOptions budget = rc.budget;
      budget.reducer = name == kReference ? "none" : name;
      ini.write(reducers::BudgetOptions::kSection, "reducer", budget.reducer);
      report::OutputFolder folder(top->file(name), cli_.force);
      report::writeFileAtomically(folder.file("config_used.ini"), ini.getContent());
      run->pipeline = std::make_unique<Pipeline>(ini, rc.mapping.backend, budget, folder, truth);
      runs.push_back(std::move(run));
    }
  } catch (const Error& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + exceptionLine(e));
  }

  // One thread a core, each taking whole runs. A stop request (Ctrl-C) ends each run between two
  // steps, or inside a step or the end phase (Interrupted, core/Cancellation.h); every run's
  // outputs are then written with status interrupted.
  const auto stopped = [](const CompareRun& r, const char* where) {
    const auto last = r.pipeline->lastStep();
    return std::string("interrupted by ") + Cancellation::signalName() + where +
           (last ? " after step " + std::to_string(*last) : std::string(" before the first step"));
  };
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < runs.size();) {
      CompareRun& r = *runs[i];
      bool end_phase = false;
      try {
        for (const auto& s : steps) {
          if (Cancellation::requested()) {
            r.status = "interrupted";
            r.error = stopped(r, "");
            break;
          }
          r.pipeline->process(s);
          ++r.steps_done;
        }
        if (r.status == "ok") {
          end_phase = true;
          if (on_end_phase) on_end_phase();
          r.pipeline->complete();
        }
      } catch (const Interrupted&) {
        r.status = "interrupted";
        r.error = stopped(r, end_phase ? " in the end phase," : "");
      } catch (const std::exception& e) {
        r.status = "failed";
        r.error = exceptionLine(e);
      }
    }
  };
  const std::size_t wanted = cli_.threads ? cli_.threads : std::thread::hardware_concurrency();
  const std::size_t threads = std::max<std::size_t>(1, std::min<std::size_t>(wanted, runs.size()));
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(worker);
  ProgressBar bar(*err, !cli_.quiet && err == &std::cerr && stderrIsTerminal());
  for (;;) {
    std::size_t done = 0, finished = 0;
    for (const auto& r : runs) {
      done += r->steps_done;
      finished += r->steps_done == steps.size() || r->status != "ok";
    }
    bar.update(static_cast<double>(done) / std::max<std::size_t>(1, runs.size() * steps.size()),
               std::to_string(finished) + "/" + std::to_string(runs.size()) + " runs");
    if (next >= runs.size() && finished == runs.size()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  for (auto& t : pool) t.join();
  bar.done();

  // Metrics against the reference, then every run's files.
  std::vector<report::ComparisonRow> rows;
  const CompareRun& ref = *runs.front();
  const std::size_t ref_landmarks = ref.pipeline->backend().landmarkCount();
  const std::size_t ref_poses = ref.pipeline->backend().poseCount();
  int exit_code = 0;
  std::string first_error;
  std::vector<std::string> failures;  ///< one stderr line a run that did not end ok
  // Without sensor IDs, a final map's coverage goes through the reference run's association
  // (docs/OUTPUTS.md, "Relocalization coverage").
  if (ref.status == "ok" && withoutLandmarkIds(steps))
    for (const auto& r : runs)
      if (r->status == "ok")
        r->pipeline->setFinalCoverage(
            coverageThroughReference(*ref.pipeline, *r->pipeline, metric_options.reloc_match_chi2));
  for (const auto& r : runs) {
    nlohmann::json extra = {{"rawlog", rc.rawlog},
                            {"sidecar_ini", rc.sidecar},
                            {"config", config_label_},
                            {"run", r->name}};
    metrics::ReferenceMetrics m;
    // A stop request after a run's end phase: its outputs are still written (quickly), marked.
    if (r->status == "ok" && Cancellation::requested()) {
      r->status = "interrupted";
      r->error = stopped(*r, " before its outputs were written,");
    }
    if (ref.status == "ok" && r->status == "ok") {
      m = metrics::compareWithReference(ref.pipeline->backend(), r->pipeline->backend(),
                                        metric_options.eig_max_rows);
      extra["reference_metrics"] = toJson(m);
    }
    nlohmann::json summary;
    try {
      summary = r->pipeline->finish(r->status, r->error, steps.size(), extra);
      if (r->status == "ok" && summary["status"] != "ok") {
        // An output of the run could not be written (a full disk), or its estimate diverged.
        r->status = "failed";
        r->error = summary["error"].get<std::string>();
      }
    } catch (const std::exception& e) {
      r->status = "failed";
      r->error = std::string("while saving outputs: ") + exceptionLine(e);
    }
    if (r->status != "ok") {
      exit_code = r->status == "interrupted" && exit_code != 1 ? 130 : 1;
      const std::string line = "run '" + r->name + "': " + r->error;
      if (first_error.empty()) first_error = line;
      failures.push_back((r->status == "interrupted" ? "" : "error: ") + line);
    }
    for (const auto& f : r->pipeline->budget().shadowFailures())
      failures.push_back("warning: run '" + r->name + "': " + shadowFailureLine(f));

    report::ComparisonRow row;
    row.run = r->name;
    row.reducer = r->pipeline->budget().options().reducer;
    row.backend = r->pipeline->backend().name();
    row.status = r->status;
    row.cap = r->pipeline->budget().capped()
                  ? static_cast<long long>(*r->pipeline->budget().options().max_landmarks)
                  : -1;
    row.landmarks = r->pipeline->backend().landmarkCount();
    row.poses = r->pipeline->backend().poseCount();
    if (ref_landmarks)
      row.landmarks_reduction_pct = 100.0 * (1.0 - double(row.landmarks) / double(ref_landmarks));
    if (ref_poses) row.poses_reduction_pct = 100.0 * (1.0 - double(row.poses) / double(ref_poses));
    row.evictions = r->pipeline->evictions();
    row.ate_m = m.ate, row.ale_m = m.ale, row.are_deg = m.are_deg, row.ud_pct = m.ud_percent;
    row.eig_min = m.eig_min, row.eig_max = m.eig_max;
    row.gt_trajectory_rmse_m = jsonNumber(summary, "ground_truth", "trajectory_rmse_m");
    row.gt_trajectory_max_m = jsonNumber(summary, "ground_truth", "trajectory_max_m");
    row.gt_landmark_rmse_m = jsonNumber(summary, "ground_truth", "landmark_rmse_m");
    row.nees_mean = jsonNumber(summary, "ground_truth", "nees_mean");
    row.time_s = r->pipeline->totalStepSeconds();
    row.reloc_coverage_pct = jsonNumber(summary, "relocalization", "coverage_pct");
    row.reloc_mean_landmarks = jsonNumber(summary, "relocalization", "mean_landmarks");
    rows.push_back(row);
  }

  // --relocalize: every final map (the reference's too) localizes each traversal.
  std::vector<RelocalizationResult> relocalized;
  if (!traversals.empty()) {
    std::vector<MapOfRun> maps;
    for (const auto& r : runs)
      if (r->status == "ok")
        maps.push_back({r->name, r->pipeline->folder().path(), r->pipeline->backend().landmarks(),
                        r->pipeline->mapAlignment()});
    relocalized = relocalizeAll(maps, traversals,
                                cli_.reference_trajectory.empty() ? nullptr : &reference_tum,
                                cli_.reference_trajectory, cli_.threads, cli_.force);
    addRelocalizationColumns(rows, relocalized, kReference);
    for (const auto& r : relocalized)
      if (r.status != "ok") {
        if (exit_code == 0) exit_code = r.status == "interrupted" ? 130 : 1;
        const std::string line =
            "run '" + r.run + "', --relocalize '" + r.traversal + "': " + r.error;
        if (first_error.empty()) first_error = line;
        failures.push_back((r.status == "interrupted" ? "" : "error: ") + line);
      }
  }

  try {
    report::writeComparisonCsv(top->file("comparison.csv"), rows);
    if (!traversals.empty()) writeRelocalizationCsv(top->file("relocalization.csv"), relocalized);
    const std::string title = "budget-slam compare: " + rc.rawlog + ", backend " +
                              rc.mapping.backend + ", cap " +
                              reducers::BudgetOptions::capText(rc.budget.max_landmarks) + ", " +
                              std::to_string(steps.size()) + " steps";
    std::string md = report::writeComparisonMarkdown(top->file("comparison.md"), title, rows);
    if (cli_.offline_optimum) {
      if (!rc.budget.max_landmarks)
        throw InputError("--offline-optimum needs a cap (not --cap none)");
      std::vector<FinalMap> maps;
      for (const auto& r : runs) {
        FinalMap m{r->name, {}};
        for (const auto& l : r->pipeline->backend().landmarks()) m.kept.push_back(l.id);
        maps.push_back(std::move(m));
      }
      const std::string table =
          writeOfflineOptimum(top->file("offline_optimum.csv"), rc.ini, steps,
                              ref.pipeline->onlinePoses(), maps, *rc.budget.max_landmarks);
      std::ofstream(top->file("comparison.md"), std::ios::app) << table;
      md += table;
    }

    std::vector<report::ChartPanel> panels;
    report::ChartPanel count{"landmarks in the map", "step", "landmarks", {}, false};
    for (const auto& r : runs) {
      report::Series s{r->name, {}, {}};
      const auto& counts = r->pipeline->landmarkCounts();
      for (std::size_t k = 0; k < counts.size(); ++k)
        s.x.push_back(double(steps[k].index)), s.y.push_back(double(counts[k]));
      count.series.push_back(std::move(s));
    }
    panels.push_back(std::move(count));
    const bool has_path = truth && !truth->path.empty();
    const auto gt = has_path ? metrics::toEstimateFrame(*truth) : dataset::GroundTruth();
    panels.push_back({has_path ? "robot position error against ground truth (online estimate)"
                               : "robot position difference to the reference run (online estimate)",
                      "step", "m", errorSeries(runs, has_path ? &gt : nullptr, steps.size()),
                      false});
    report::writeChartPng(top->file("comparison.png"), panels);
    nlohmann::json summary = {
        {"status", exit_code == 0 ? "ok" : (exit_code == 130 ? "interrupted" : "failed")},
        {"error", first_error},
        {"rawlog", rc.rawlog},
        {"sidecar_ini", rc.sidecar},
        {"config", config_label_},
        {"runs", names.size() + 1},
        {"steps", steps.size()},
        {"threads", threads}};
    if (!top->earlierRun().empty()) summary["earlier_run_moved_to"] = top->earlierRun();
    report::writeJson(top->file("summary.json"), summary);
    if (!cli_.quiet) *out << md << "outputs in " << top->path() << "/\n";
  } catch (const std::exception& e) {
    return fail(std::string("while saving outputs: ") + exceptionLine(e));
  }
  // One line a run that failed or was interrupted (the reference's failure fails every
  // comparison, but the others' errors are their own), and a warning a failed shadow reducer.
  for (const auto& line : failures) *err << "budget-slam: " << printable(line) << std::endl;
  return exit_code;
}

}  // namespace budget_slam::app
