#include "budget_slam/report/ComparisonTable.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/FileWrite.h"

namespace budget_slam::report {
namespace {

/// Fixed or scientific, whichever reads better, "-" for NaN.
std::string shown(double v, int digits = 4) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream o;
  if (v != 0 && (std::abs(v) < 1e-3 || std::abs(v) >= 1e5))
    o << std::scientific << std::setprecision(2) << v;
  else
    o << std::fixed << std::setprecision(digits) << v;
  return o.str();
}

std::string withPct(std::size_t n, double pct) {
  return std::to_string(n) + (std::isfinite(pct) ? " [" + shown(pct, 0) + "%]" : "");
}

/// The relocalization table under the main one: coverage of each final map over the rawlog and,
/// with compare --relocalize, how it localized the other traversals.
std::string relocalizationMarkdown(const std::vector<ComparisonRow>& rows) {
  bool traversals = false;
  for (const auto& r : rows) traversals |= std::isfinite(r.reloc_rmse_m) || std::isfinite(r.reloc_lost_pct);
  std::ostringstream md;
  md << "\n| run | reloc coverage (%) | map landmarks seen a step";
  if (traversals)
    md << " | reloc RMSE (m) | reloc max (m) | lost (%) | traversal coverage (%) | RMSE ratio | lost "
          "ratio | success per place (%)";
  md << " |\n|---|---|---" << (traversals ? "|---|---|---|---|---|---|---" : "") << "|\n";
  for (const auto& r : rows) {
    md << "| " << r.run << " | " << shown(r.reloc_coverage_pct, 1) << " | "
       << shown(r.reloc_mean_landmarks, 2);
    if (traversals)
      md << " | " << shown(r.reloc_rmse_m) << " | " << shown(r.reloc_max_m) << " | "
         << shown(r.reloc_lost_pct, 1) << " | " << shown(r.reloc_traversal_coverage_pct, 1) << " | "
         << shown(r.reloc_rmse_ratio, 2) << " | " << shown(r.reloc_lost_ratio, 2) << " | "
         << shown(r.reloc_success_pct, 1);
    md << " |\n";
  }
  md << "\nReloc coverage: share of the rawlog's steps at which the robot observed at least k "
        "landmarks of the run's final map ([Metrics] reloc_min_landmarks).";
  if (traversals)
    md << " Reloc RMSE, max, lost, traversal coverage: the final map localizing the --relocalize "
          "traversals (budget-slam localize), mean over the traversals, over their steps in the "
          "reference run's mapped area; ratios: to the reference map's; success per place: the "
          "share of a place's steps tracked ([Localization] success_xy, success_yaw_deg), mean "
          "over places.";
  md << "\n";
  return md.str();
}

}  // namespace

void writeComparisonCsv(const std::string& path, const std::vector<ComparisonRow>& rows) {
  CsvWriter csv(path, {"run",
                       "reducer",
                       "backend",
                       "status",
                       "cap",
                       "landmarks",
                       "landmarks_reduction_pct",
                       "poses",
                       "poses_reduction_pct",
                       "evictions",
                       "ate_m",
                       "ale_m",
                       "are_deg",
                       "ud_pct",
                       "eig_min",
                       "eig_max",
                       "gt_trajectory_rmse_m",
                       "gt_trajectory_max_m",
                       "gt_landmark_rmse_m",
                       "nees_mean",
                       "time_s",
                       "reloc_coverage_pct",
                       "reloc_mean_landmarks",
                       "reloc_rmse_m",
                       "reloc_max_m",
                       "reloc_lost_pct",
                       "reloc_traversal_coverage_pct",
                       "reloc_rmse_ratio",
                       "reloc_lost_ratio",
                       "reloc_success_pct",
                       "reloc_scored_pct"},
                CsvWriter::Mode::WholeFile);
  for (const auto& r : rows) {
    csv.cell(r.run).cell(r.reducer).cell(r.backend).cell(r.status);
    if (r.cap >= 0)
      csv.cell(r.cap);
    else
      csv.cell(std::string());
    csv.cell(r.landmarks)
        .cell(r.landmarks_reduction_pct)
        .cell(r.poses)
        .cell(r.poses_reduction_pct)
        .cell(r.evictions)
        .cell(r.ate_m)
        .cell(r.ale_m)
        .cell(r.are_deg)
        .cell(r.ud_pct)
        .cell(r.eig_min)
        .cell(r.eig_max)
        .cell(r.gt_trajectory_rmse_m)
        .cell(r.gt_trajectory_max_m)
        .cell(r.gt_landmark_rmse_m)
        .cell(r.nees_mean)
        .cell(r.time_s)
        .cell(r.reloc_coverage_pct)
        .cell(r.reloc_mean_landmarks)
        .cell(r.reloc_rmse_m)
        .cell(r.reloc_max_m)
        .cell(r.reloc_lost_pct)
        .cell(r.reloc_traversal_coverage_pct)
        .cell(r.reloc_rmse_ratio)
        .cell(r.reloc_lost_ratio)
        .cell(r.reloc_success_pct)
        .cell(r.reloc_scored_pct);
    csv.endRow();
  }
  csv.close();
}

std::string writeComparisonMarkdown(const std::string& path, const std::string& title,
                                    const std::vector<ComparisonRow>& rows) {
  std::ostringstream md;
  md << "### " << title << "\n\n";
  md << "| run | backend | cap | landmarks [reduction] | poses [reduction] | dropped | ATE (m) | "
        "ALE (m) | ARE (deg) | UD (%) | EIG [min, max] | GT traj RMSE (m) | GT traj max (m) | "
        "GT landmark RMSE (m) | NEES | time (s) |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    md << "| " << r.run << (r.status == "ok" ? "" : " (" + r.status + ")") << " | " << r.backend
       << " | " << (r.cap >= 0 ? std::to_string(r.cap) : "-") << " | "
       << withPct(r.landmarks, r.landmarks_reduction_pct) << " | "
       << withPct(r.poses, r.poses_reduction_pct) << " | " << r.evictions << " | " << shown(r.ate_m)
       << " | " << shown(r.ale_m) << " | " << shown(r.are_deg) << " | " << shown(r.ud_pct, 2)
       << " | "
       << (std::isfinite(r.eig_min) ? "[" + shown(r.eig_min) + ", " + shown(r.eig_max) + "]" : "-")
       << " | " << shown(r.gt_trajectory_rmse_m) << " | " << shown(r.gt_trajectory_max_m) << " | "
       << shown(r.gt_landmark_rmse_m) << " | " << shown(r.nees_mean, 2) << " | "
       << shown(r.time_s, 2) << " |\n";
  }
  md << "\nATE, ALE, ARE, UD, EIG: against the unreduced reference run over the poses and "
        "landmarks "
        "each run kept (Choudhary et al. Sec. V-B). GT: against ground truth. NEES: mean "
        "normalized estimation error squared of the robot pose (3 = consistent).\n";
  md << relocalizationMarkdown(rows);
  writeFileAtomically(path, md.str());
  return md.str();
}

}  // namespace budget_slam::report
