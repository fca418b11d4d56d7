// compare --relocalize: every run's final map localizes other traversals (docs/OUTPUTS.md).
#include "budget_slam/localization/Relocalize.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/WorkerThreads.h"
#include "budget_slam/engine/ProcessProbes.h"
#include "budget_slam/localization/Localizer.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/report/CsvWriter.h"

namespace budget_slam::runs {
namespace {

double meanOfFinite(const std::vector<double>& v) {
  double s = 0;
  std::size_t n = 0;
  for (double x : v)
    if (std::isfinite(x)) s += x, ++n;
  return n ? s / n : std::numeric_limits<double>::quiet_NaN();
}

/// a / b, with 0 / 0 = 1 (both maps perfect) and x / 0 undefined.
/// What traversal `t` localized in map `m` was given (its summary.json).
runs::RunGiven mapGiven(const Traversal& t, const MapOfRun& m) {
  runs::RunGiven g;
  g.rawlog = t.rawlog, g.map = m.folder;
  return g;
}

double ratio(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b)) return std::numeric_limits<double>::quiet_NaN();
  if (b == 0) return a == 0 ? 1.0 : std::numeric_limits<double>::quiet_NaN();
  return a / b;
}

}  // namespace

std::vector<RelocalizationResult> relocalizeAll(const std::vector<MapOfRun>& maps,
                                                const std::vector<Traversal>& traversals,
                                                const std::vector<TrajectoryPoint>* reference,
                                                const std::string& reference_file, unsigned threads,
                                                bool force, ProgressReporter* progress) {
  std::vector<RelocalizationResult> results;
  for (const auto& m : maps)
    for (const auto& t : traversals) {
      RelocalizationResult r;
      r.run = m.run;
      r.traversal = t.name;
      results.push_back(r);
    }
  std::atomic<std::size_t> next{0}, steps_done{0}, ended{0};
  std::size_t steps_total = 0;
  for (std::size_t i = 0; i < results.size(); ++i)
    steps_total += traversals[i % traversals.size()].steps.size();
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < results.size();) {
      auto& r = results[i];
      const MapOfRun& m = maps[i / traversals.size()];
      const Traversal& t = traversals[i % traversals.size()];
      std::unique_ptr<Localizer> loc;
      try {
        if (m.landmarks.size() > t.localization.max_map_landmarks)
          throw ConfigError("the map of '" + m.run + "' has " + std::to_string(m.landmarks.size()) +
                            " landmarks, more than [Localization] max_map_landmarks = " +
                            std::to_string(t.localization.max_map_landmarks));
        if (!t.truth.path.empty() && !m.alignment && !reference)
          throw InputError("run '" + m.run + "' has no ground-truth alignment for '" + t.name +
                           "'");
        metrics::MetricsOptions mo;
        mo.loadFromConfigFile(t.ini, metrics::MetricsOptions::kSection);
        auto inputs = resolveLocalization(t.steps, t.steps_in_rawlog, t.truth, m.alignment,
                                          std::nullopt, reference, reference_file, t.localization);
        inputs.mapping_path = m.mapping_path;
        report::OutputFolder folder(
            (std::filesystem::path(m.folder) / "relocalize" / t.name).string(), force);
        writeFileAtomically(folder.file("config_used.ini"), t.config_used);
        loc = std::make_unique<Localizer>(t.ini, t.localization, mo.reloc_min_landmarks, folder,
                                          m.landmarks, inputs);
        for (const auto& s : t.steps) {
          if (Cancellation::requested()) {
            r.status = runs::RunStatus::Interrupted, r.kind = runs::ErrorKind::Stopped;
            r.error = std::string("interrupted by ") + Cancellation::signalName();
            break;
          }
          loc->process(s);
          ++steps_done;
        }
        runs::RunGiven given = mapGiven(t, m);
        given.run = m.run;
        loc->finish(r.status, r.kind, r.error, given);
        r.score = loc->score();
      } catch (const std::exception& e) {
        r.status = runs::RunStatus::Failed, r.kind = runs::errorKindOf(e);
        r.error = e.what();
        if (loc) try {
            loc->finish(r.status, r.kind, r.error, mapGiven(t, m));
          } catch (const std::exception&) {
          }
      }
      ++ended;
    }
  };
  const std::size_t n = std::max<std::size_t>(
      1, std::min<std::size_t>(threads ? threads : runs::availableCpus(), results.size()));
  WorkerThreads pool(n, worker);
  // Every localization costs about the same a step: the elapsed time scaled by the steps left is
  // an honest ETA here.
  while (progress && pool.started() > 0 && ended < results.size()) {
    const std::size_t d = steps_done;
    progress->update(
        static_cast<double>(d) / std::max<std::size_t>(1, steps_total), d, steps_total,
        std::to_string(ended) + "/" + std::to_string(results.size()) + " localizations done");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  pool.join();
  if (progress) progress->finish(ended == results.size());
  return results;
}

void writeRelocalizationCsv(const std::string& path,
                            const std::vector<RelocalizationResult>& results) {
  report::CsvWriter csv(path, {"run", "traversal", "status", "rmse_m", "max_m", "lost_pct",
                               "coverage_pct", "nees_mean", "success_pct", "scored_pct"});
  for (const auto& r : results) {
    csv.cell(r.run)
        .cell(r.traversal)
        .cell(runs::statusName(r.status))
        .cell(r.score.rmse_m)
        .cell(r.score.max_m)
        .cell(r.score.lost_pct)
        .cell(r.score.coverage_pct)
        .cell(r.score.nees_mean)
        .cell(r.score.success_pct)
        .cell(r.score.scored_pct);
    csv.endRow();
  }
}

void addRelocalizationColumns(std::vector<report::ComparisonRow>& rows,
                              const std::vector<RelocalizationResult>& results,
                              const std::string& reference_run) {
  std::map<std::string, std::vector<const RelocalizationResult*>> by_run;
  for (const auto& r : results) by_run[r.run].push_back(&r);
  const auto mean = [&](const std::string& run, double metrics::LocalizationScore::*field) {
    std::vector<double> v;
    for (const auto* r : by_run[run])
      v.push_back(r->status == runs::RunStatus::Ok ? r->score.*field : NAN);
    return meanOfFinite(v);
  };
  using S = metrics::LocalizationScore;
  for (auto& row : rows) {
    if (!by_run.count(row.run)) continue;
    row.reloc_rmse_m = mean(row.run, &S::rmse_m);
    row.reloc_max_m = mean(row.run, &S::max_m);
    row.reloc_lost_pct = mean(row.run, &S::lost_pct);
    row.reloc_traversal_coverage_pct = mean(row.run, &S::coverage_pct);
    row.reloc_success_pct = mean(row.run, &S::success_pct);
    row.reloc_scored_pct = mean(row.run, &S::scored_pct);
  }
  const report::ComparisonRow* ref = nullptr;
  for (const auto& row : rows)
    if (row.run == reference_run) ref = &row;
  if (!ref) return;
  const double ref_rmse = ref->reloc_rmse_m, ref_lost = ref->reloc_lost_pct;
  for (auto& row : rows) {
    row.reloc_rmse_ratio = ratio(row.reloc_rmse_m, ref_rmse);
    row.reloc_lost_ratio = ratio(row.reloc_lost_pct, ref_lost);
  }
}

}  // namespace budget_slam::runs
