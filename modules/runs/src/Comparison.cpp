#include "budget_slam/runs/Comparison.h"

#include <cmath>
#include <optional>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/RunStatus.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/runs/RunConfig.h"

namespace budget_slam::runs {
namespace {

/// What summary.json holds of a number: a non-finite value is null there, missing in the table.
double finiteOrNaN(double v) {
  return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
}

/// Position error over the steps of each run, against `truth` rows or the reference run.
std::vector<report::Series> errorSeries(const CompareRuns& runs, const dataset::GroundTruth* truth,
                                        std::size_t steps) {
  std::vector<report::Series> out;
  const auto* ref = runs.front()->driver.get();
  for (const auto& r : runs) {
    if (!truth && r->name == kReferenceRun) continue;
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

}  // namespace

/// The reference run (reducer none) and one run a reducer of `names` (with `seeds`: one a reducer
/// and seed, named <reducer>/seed<S>), each with its folder under `top` and its config_used.ini,
/// appended to `runs` one by one (on an error, the runs made so far are there to say why in their
/// summary.json). `base` is every run's driver specification but its reducer and seed. The
/// reference drops nothing, so no seed changes it: it runs once.
void makeRuns(const mrpt::config::CConfigFileMemory& merged, const BackendRegistry& backends,
              const DriverSpec& base, const std::vector<std::string>& names,
              const std::vector<std::uint64_t>& seeds, const report::OutputFolder& top, bool force,
              const std::shared_ptr<dataset::GroundTruth>& truth, CompareRuns& runs) {
  struct Planned {
    std::string name, reducer;
    std::optional<std::uint64_t> seed;
  };
  std::vector<Planned> all = {{kReferenceRun, "none", std::nullopt}};
  for (const auto& n : names) {
    if (seeds.empty()) all.push_back({n, n, std::nullopt});
    for (const auto s : seeds) all.push_back({n + "/seed" + std::to_string(s), n, s});
  }
  for (const auto& [name, reducer, seed] : all) {
    auto run = std::make_unique<CompareRun>();
    run->name = name;
    mrpt::config::CConfigFileMemory ini;
    copyIni(merged, ini);  // no second ${...} expansion
    reducers::BudgetOptions budget = base.budget;
    budget.reducer = reducer;
    ini.write(reducers::BudgetOptions::kSection, "reducer", budget.reducer);
    if (seed) {
      budget.seed = *seed;
      ini.write(reducers::BudgetOptions::kSection, "seed", std::to_string(*seed));
    }
    std::optional<report::OutputFolder> folder;
    try {
      folder.emplace(top.file(name), force);
      writeFileAtomically(folder->file("config_used.ini"), configUsed(ini));
      DriverSpec spec = base;
      spec.budget = budget;
      spec.keep_history = true;  // the comparison's figures need every run's history
      run->driver = std::make_unique<RunDriver>(ini, backends, spec, *folder, truth);
    } catch (const std::exception& e) {
      // The run whose making failed (few file descriptors, a full disk) says its own error in
      // its own folder, when it has one; when even that cannot be written (no descriptor left
      // for it), the comparison's line says so.
      std::string not_saved;
      if (folder) try {
          RunOutcome o;
          o.fail(RunStatus::Failed, errorKindOf(e), printable(exceptionLine(e)));
          o.given.started = false, o.given.run = name;
          writeSummary(folder->file("summary.json"), o);
        } catch (const std::exception& s) {
          not_saved = "its summary.json not written either: " + exceptionLine(s);
        }
      if (not_saved.empty()) throw;
      throw Error(withAlso(exceptionLine(e), not_saved));
    }
    runs.push_back(std::move(run));
  }
}

/// Ends run `r`: its metrics against the reference (when both are ok) and its outputs
/// (RunDriver::finish, with `given` and the metrics in summary.json). A run whose outputs could not
/// be written, or whose estimate is not finite, becomes failed.
metrics::ReferenceMetrics finishRun(CompareRun& r, const CompareRun& ref, std::size_t steps,
                                    std::size_t eig_max_rows, RunGiven given) {
  metrics::ReferenceMetrics m;
  // A stop request after a run's end phase, or while its metrics were computed (EIG: seconds on
  // long graph runs): its outputs are still written (quickly), marked.
  const auto mark_stopped = [&r] {
    if (r.ok() && Cancellation::requested()) {
      r.status = RunStatus::Interrupted, r.kind = ErrorKind::Stopped;
      r.error = interruptedLine(r, " before its outputs were written,");
    }
  };
  mark_stopped();
  if (ref.ok() && r.ok()) {
    m = metrics::compareWithReference(ref.driver->backend(), r.driver->backend(), eig_max_rows);
    given.reference_metrics = m;
    mark_stopped();
  }
  try {
    r.result = r.driver->finish(r.status, r.kind, r.error, steps, given);
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
  row.status = statusName(r.status);
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

/// comparison.<png|pdf|svg>: the landmark count over the steps (the cap marked), and the robot
/// position error against ground truth (else the difference to the reference run); the
/// reference dashed black.
void writeComparisonChart(const report::OutputFolder& top, const std::string& title,
                          const CompareRuns& runs, const std::vector<Step>& steps,
                          const dataset::GroundTruth* truth, std::optional<std::size_t> cap,
                          const std::vector<report::FigureFormat>& formats) {
  std::vector<report::ChartPanel> panels;
  report::ChartPanel count{"landmarks in the map", "step", "landmarks", {}, false, {}, true};
  if (cap) count.marks.push_back({double(*cap), "cap " + std::to_string(*cap)});
  for (const auto& r : runs) {
    report::Series s{r->name, {}, {}, r->name == kReferenceRun};
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
  for (auto& s : panels.back().series) s.reference = s.name == kReferenceRun;
  for (const auto format : formats)
    report::writeChart(top.file(report::figureFile("comparison", format)), title, panels, format);
}

}  // namespace budget_slam::runs
