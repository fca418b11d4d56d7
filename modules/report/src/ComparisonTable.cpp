#include "budget_slam/report/ComparisonTable.h"

#include <cmath>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/FileWrite.h"

namespace budget_slam::report {
namespace {

using Row = ComparisonRow;
using Table = ComparisonColumn::Table;

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

ComparisonCell text(std::string s) { return {std::move(s), Row::kNaN, true, false}; }
ComparisonCell number(double v) { return {"", v, false, false}; }
ComparisonCell integer(double v) { return {"", v, false, true}; }

/// A number column; `digits` decimals in comparison.md.
ComparisonColumn num(std::string name, double Row::*field, Table table = Table::CsvOnly,
                     std::string heading = "", int digits = 4) {
  return {std::move(name),
          [field](const Row& r) { return number(r.*field); },
          table,
          std::move(heading),
          [field, digits](const Row& r) { return shown(r.*field, digits); },
          false,
          digits};
}

ComparisonColumn count(std::string name, std::size_t Row::*field, Table table = Table::CsvOnly,
                       std::string heading = "") {
  return {std::move(name),
          [field](const Row& r) { return integer(double(r.*field)); },
          table,
          std::move(heading),
          [field](const Row& r) { return std::to_string(r.*field); },
          false,
          1};
}

/// -1 (none) is an empty field and "-".
ComparisonColumn optionalInteger(std::string name, long long Row::*field, Table table,
                                 std::string heading) {
  return {std::move(name),
          [field](const Row& r) { return integer(r.*field >= 0 ? double(r.*field) : Row::kNaN); },
          table, std::move(heading),
          [field](const Row& r) { return r.*field >= 0 ? std::to_string(r.*field) : "-"; }};
}

ComparisonColumn textColumn(std::string name, std::string Row::*field) {
  return {std::move(name), [field](const Row& r) { return text(r.*field); }, Table::CsvOnly, "",
          nullptr};
}

/// Marks `column` for the table over seeds.
ComparisonColumn overSeeds(ComparisonColumn column) {
  column.over_seeds = true;
  return column;
}

std::vector<ComparisonColumn> makeColumns() {
  std::vector<ComparisonColumn> c;
  c.push_back(
      {"run", [](const Row& r) { return text(r.run); }, Table::Main, "run",
       [](const Row& r) { return r.run + (r.status == "ok" ? "" : " (" + r.status + ")"); }});
  c.push_back(textColumn("reducer", &Row::reducer));
  c.push_back(textColumn("backend", &Row::backend));
  c.push_back(textColumn("status", &Row::status));
  c.push_back(optionalInteger("cap", &Row::cap, Table::Main, "cap"));
  c.push_back(optionalInteger("seed", &Row::seed, Table::Main, "seed"));
  c.push_back(overSeeds(num("gt_trajectory_rmse_aligned_m", &Row::gt_trajectory_rmse_aligned_m,
                            Table::Main, "ATE vs GT, aligned (m)")));
  c.push_back(overSeeds(num("gt_trajectory_rpe_10m_m", &Row::gt_trajectory_rpe_10m_m, Table::Main,
                            "RPE (m / 10 m)")));
  c.push_back(overSeeds(
      {"landmarks", [](const Row& r) { return integer(double(r.landmarks)); }, Table::Main,
       "landmarks [reduction]",
       [](const Row& r) { return withPct(r.landmarks, r.landmarks_reduction_pct); }, false, 1}));
  c.push_back(num("landmarks_reduction_pct", &Row::landmarks_reduction_pct));
  c.push_back({"poses", [](const Row& r) { return integer(double(r.poses)); }, Table::Main,
               "poses [reduction]",
               [](const Row& r) { return withPct(r.poses, r.poses_reduction_pct); }});
  c.push_back(num("poses_reduction_pct", &Row::poses_reduction_pct));
  c.push_back(overSeeds(count("evictions", &Row::evictions, Table::Main, "dropped")));
  c.push_back(overSeeds(count("refused", &Row::refused, Table::Main, "refused")));
  c.push_back(overSeeds(num("ref_ate_m", &Row::ref_ate_m, Table::Main, "ATE vs ref (m)")));
  c.push_back(overSeeds(num("ref_ale_m", &Row::ref_ale_m, Table::Main, "ALE vs ref (m)")));
  c.push_back(num("ref_are_deg", &Row::ref_are_deg, Table::Main, "ARE vs ref (deg)"));
  c.push_back(num("ref_ud_pct", &Row::ref_ud_pct, Table::Main, "UD (%)", 2));
  c.push_back(
      overSeeds(num("ref_ud_std_factor", &Row::ref_ud_std_factor, Table::Main, "pose std ×", 2)));
  c.push_back({"ref_eig_min", [](const Row& r) { return number(r.ref_eig_min); }, Table::Main,
               "EIG [min, max]",
               [](const Row& r) {
                 return std::isfinite(r.ref_eig_min)
                            ? "[" + shown(r.ref_eig_min) + ", " + shown(r.ref_eig_max) + "]"
                            : std::string("-");
               }});
  c.push_back(num("ref_eig_max", &Row::ref_eig_max));
  c.push_back(num("gt_trajectory_rmse_m", &Row::gt_trajectory_rmse_m, Table::Main,
                  "GT traj RMSE, start frame (m)"));
  c.push_back(num("gt_trajectory_max_m", &Row::gt_trajectory_max_m));
  c.push_back(num("gt_landmark_rmse_m", &Row::gt_landmark_rmse_m));
  c.push_back(num("gt_landmark_rmse_aligned_m", &Row::gt_landmark_rmse_aligned_m, Table::Main,
                  "GT landmark RMSE, aligned (m)"));
  c.push_back(overSeeds(num("nees_mean", &Row::nees_mean, Table::Main, "NEES", 2)));
  c.push_back(num("time_s", &Row::time_s, Table::Main, "time (s)", 2));
  c.push_back(overSeeds(num("reloc_coverage_pct", &Row::reloc_coverage_pct, Table::Relocalization,
                            "reloc coverage (%)", 1)));
  c.push_back(num("reloc_mean_landmarks", &Row::reloc_mean_landmarks, Table::Relocalization,
                  "map landmarks seen a step", 2));
  c.push_back(
      overSeeds(num("reloc_rmse_m", &Row::reloc_rmse_m, Table::Traversals, "reloc RMSE (m)")));
  c.push_back(num("reloc_max_m", &Row::reloc_max_m, Table::Traversals, "reloc max (m)"));
  c.push_back(
      overSeeds(num("reloc_lost_pct", &Row::reloc_lost_pct, Table::Traversals, "lost (%)", 1)));
  c.push_back(num("reloc_traversal_coverage_pct", &Row::reloc_traversal_coverage_pct,
                  Table::Traversals, "traversal coverage (%)", 1));
  c.push_back(num("reloc_rmse_ratio", &Row::reloc_rmse_ratio, Table::Traversals, "RMSE ratio", 2));
  c.push_back(num("reloc_lost_ratio", &Row::reloc_lost_ratio, Table::Traversals, "lost ratio", 2));
  c.push_back(overSeeds(num("reloc_success_pct", &Row::reloc_success_pct, Table::Traversals,
                            "success per place (%)", 1)));
  c.push_back(num("reloc_scored_pct", &Row::reloc_scored_pct));
  return c;
}

/// A markdown table of the columns in `tables` (the run's name first), one row a run.
std::string markdownTable(const std::vector<Row>& rows, const std::set<Table>& tables) {
  std::vector<const ComparisonColumn*> shownColumns;
  std::set<long long> seeds;
  for (const auto& r : rows) seeds.insert(r.seed);
  for (const auto& col : comparisonColumns()) {
    if (col.name != "run" && !tables.count(col.table)) continue;
    if (col.name == "seed" && seeds.size() < 2) continue;  // one seed: said in the title
    shownColumns.push_back(&col);
  }
  std::ostringstream md;
  md << "|";
  for (const auto* col : shownColumns) md << " " << col->heading << " |";
  md << "\n|";
  for (std::size_t i = 0; i < shownColumns.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& r : rows) {
    md << "|";
    for (const auto* col : shownColumns) md << " " << col->shown(r) << " |";
    md << "\n";
  }
  return md.str();
}

/// compare --seeds: a row a reducer (the reference too), the mean ± std over its runs that ended
/// ok of each column marked over_seeds (comparison.csv's names head the columns); empty when no
/// reducer ran with more than one seed.
std::string overSeedsTable(const std::vector<Row>& rows) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const Row*>> by_reducer;
  std::map<std::string, std::size_t> runs;
  for (const auto& r : rows) {
    if (!runs.count(r.reducer)) order.push_back(r.reducer);
    ++runs[r.reducer];
    if (r.status == "ok") by_reducer[r.reducer].push_back(&r);
  }
  bool several = false;
  for (const auto& [reducer, n] : runs) several |= n > 1;
  if (!several) return "";
  std::vector<const ComparisonColumn*> columns;
  for (const auto& col : comparisonColumns())
    if (col.over_seeds) columns.push_back(&col);
  std::ostringstream md;
  md << "\nMean ± std over the seeds (runs that ended ok):\n\n| reducer | runs ok |";
  for (const auto* col : columns) md << " " << col->name << " |";
  md << "\n|---|---|";
  for (std::size_t i = 0; i < columns.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& reducer : order) {
    const auto& ok = by_reducer[reducer];
    md << "| " << reducer << " | " << ok.size() << "/" << runs[reducer] << " |";
    for (const auto* col : columns) {
      std::vector<double> v;
      for (const Row* r : ok)
        if (const double x = col->value(*r).number; std::isfinite(x)) v.push_back(x);
      if (v.empty()) {
        md << " - |";
        continue;
      }
      double mean = 0, var = 0;
      for (const double x : v) mean += x;
      mean /= v.size();
      for (const double x : v) var += (x - mean) * (x - mean);
      const double sd = v.size() > 1 ? std::sqrt(var / (v.size() - 1)) : 0.0;
      md << " " << shown(mean, col->digits)
         << (v.size() > 1 ? " ± " + shown(sd, col->digits) : std::string()) << " |";
    }
    md << "\n";
  }
  md << "\nstd: the sample standard deviation over the seeds. Paired tests between reducers over "
        "seeds (Wilcoxon signed-rank): tools/experiments/sweep (docs/EXPERIMENTS.md).\n";
  return md.str();
}

}  // namespace

const std::vector<ComparisonColumn>& comparisonColumns() {
  static const std::vector<ComparisonColumn> columns = makeColumns();
  return columns;
}

void writeComparisonCsv(const std::string& path, const std::vector<ComparisonRow>& rows) {
  std::vector<std::string> names;
  for (const auto& col : comparisonColumns()) names.push_back(col.name);
  CsvWriter csv(path, names, CsvWriter::Mode::WholeFile);
  for (const auto& r : rows) {
    for (const auto& col : comparisonColumns()) {
      const ComparisonCell cell = col.value(r);
      if (cell.is_text)
        csv.cell(cell.text);
      else if (cell.is_integer && std::isfinite(cell.number))
        csv.cell(static_cast<long long>(cell.number));
      else
        csv.cell(cell.number);
    }
    csv.endRow();
  }
  csv.close();
}

std::string writeComparisonMarkdown(const std::string& path, const std::string& title,
                                    const std::vector<ComparisonRow>& rows) {
  std::ostringstream md;
  md << "### " << title << "\n\n" << markdownTable(rows, {Table::Main});
  md << "\nATE vs GT, aligned: RMSE of the robot position against ground truth after the rigid 2D "
        "transform that fits the trajectory to it best (evo_ape --align). RPE: drift, the RMSE of "
        "the translational relative pose error over every stretch of 10 m of ground-truth path, "
        "from "
        "each pose to the first one 10 m of path further on (evo_rpe --delta 10 --delta_unit m "
        "--all_pairs, which ends a stretch at the pose nearest to 10 m). Dropped: landmarks "
        "removed after "
        "holding a place in the map; refused: newcomers not admitted ([LandmarkBudget] admission = "
        "compete). vs ref: against the unreduced reference run over the poses and landmarks each "
        "run kept (Choudhary et al. Sec. V-B): ATE (positions), ALE (landmarks), ARE (heading); "
        "UD, the uncertainty difference: the percentage increase of the determinant of the latest "
        "pose's 3x3 covariance (Eq. 12), which grows with the sixth power of its standard "
        "deviations, so pose std × = (1 + UD/100)^(1/6) is the factor by which they grew "
        "(geometric mean); EIG: the range of the eigenvalues of Σ_reference − Σ_run over the "
        "variables both runs hold (Eq. 11), all ≤ 0 when the run is conservative (at least as "
        "uncertain as the unreduced run in every direction), a positive max where it is more "
        "certain. GT traj RMSE, start frame: against ground truth without alignment (an early "
        "heading error turns the whole estimate). NEES: mean normalized estimation error squared "
        "of the robot pose against ground truth in the start frame (3 = consistent).\n";

  md << overSeedsTable(rows);

  bool traversals = false;
  for (const auto& r : rows)
    traversals |= std::isfinite(r.reloc_rmse_m) || std::isfinite(r.reloc_lost_pct);
  md << "\n"
     << (traversals ? markdownTable(rows, {Table::Relocalization, Table::Traversals})
                    : markdownTable(rows, {Table::Relocalization}));
  md << "\nReloc coverage: share of the rawlog's steps at which the robot observed at least k "
        "landmarks of the run's final map ([Metrics] reloc_min_landmarks).";
  if (traversals)
    md << " Reloc RMSE, max, lost, traversal coverage: the final map localizing the --relocalize "
          "traversals (budget-slam localize), mean over the traversals, over their steps in the "
          "reference run's mapped area; ratios: to the reference map's; success per place: the "
          "share of a place's steps tracked ([Localization] success_xy, success_yaw_deg), mean "
          "over places.";
  md << "\n";
  writeFileAtomically(path, md.str());
  return md.str();
}

}  // namespace budget_slam::report
