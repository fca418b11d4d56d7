#pragma once
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace budget_slam::report {

/// One run of `compare` (docs/OUTPUTS.md: comparison.csv / comparison.md). SI units; NaN where
/// a value does not apply (e.g. no ground truth): an empty field in the CSV, "-" in the table.
struct ComparisonRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string run;      ///< folder name: reference or the reducer's name (seed<S>/<reducer>)
  std::string reducer;  ///< none for the reference
  std::string backend;
  std::string status;   ///< ok | failed | interrupted
  long long cap = -1;   ///< -1: no cap
  long long seed = -1;  ///< [LandmarkBudget] seed of the run
  /// Against ground truth after the rigid 2D alignment (evo_ape --align): the ATE [m].
  double gt_trajectory_rmse_aligned_m = kNaN;
  /// Drift: translational RPE over 10 m of ground-truth path (metrics/RelativePoseError.h) [m].
  double gt_trajectory_rpe_10m_m = kNaN;
  std::size_t landmarks = 0;
  double landmarks_reduction_pct = kNaN;  ///< 100 (1 - landmarks / reference landmarks)
  std::size_t poses = 0;
  double poses_reduction_pct = kNaN;
  std::size_t evictions = 0;  ///< landmarks dropped after holding a place (steps.csv n_dropped)
  std::size_t refused = 0;    ///< newcomers refused at admission (steps.csv n_refused)
  /// Against the unreduced reference run (Choudhary et al. Sec. V-B, metrics/ReferenceMetrics.h).
  double ref_ate_m = kNaN, ref_ale_m = kNaN, ref_are_deg = kNaN, ref_ud_pct = kNaN;
  double ref_ud_std_factor = kNaN;  ///< UD as the growth of the pose's standard deviations
  double ref_eig_min = kNaN, ref_eig_max = kNaN;
  /// Against ground truth in the start frame (no alignment).
  double gt_trajectory_rmse_m = kNaN, gt_trajectory_max_m = kNaN, gt_landmark_rmse_m = kNaN;
  double gt_landmark_rmse_aligned_m = kNaN;
  double nees_mean = kNaN;
  double time_s = kNaN;  ///< wall time of the SLAM steps
  /// Relocalization coverage of the final map over the rawlog's steps (docs/OUTPUTS.md).
  double reloc_coverage_pct = kNaN, reloc_mean_landmarks = kNaN;
  /// compare --relocalize: the final map localizing each traversal, mean over the traversals.
  double reloc_rmse_m = kNaN, reloc_max_m = kNaN, reloc_lost_pct = kNaN;
  double reloc_traversal_coverage_pct = kNaN;
  /// reloc_rmse_m and reloc_lost_pct over the reference map's.
  double reloc_rmse_ratio = kNaN, reloc_lost_ratio = kNaN;
  /// compare --relocalize, mean over the traversals: relocalization success per place [%] and
  /// the share of the traversals' steps scored (in the mapped area) [%] (docs/OUTPUTS.md).
  double reloc_success_pct = kNaN, reloc_scored_pct = kNaN;
};

/// What a cell of comparison.csv holds: text, or a number (NaN: empty field).
struct ComparisonCell {
  std::string text;
  double number = ComparisonRow::kNaN;
  bool is_text = false, is_integer = false;
};

/// One column of the comparison: its comparison.csv name and, when comparison.md shows it, the
/// table it goes to and how. The one list of columns is comparisonColumns(): a new column is one
/// entry there (and a field of ComparisonRow).
struct ComparisonColumn {
  enum class Table { CsvOnly, Main, Relocalization, Traversals };
  std::string name;  ///< comparison.csv header
  std::function<ComparisonCell(const ComparisonRow&)> value;
  Table table = Table::CsvOnly;
  std::string heading;  ///< comparison.md header
  /// comparison.md cell (default: the value, 4 decimals, "-" when missing).
  std::function<std::string(const ComparisonRow&)> shown;
  /// In comparison.md's "mean ± std over the seeds" table (compare --seeds).
  bool over_seeds = false;
  int digits = 4;  ///< decimals of a number in comparison.md
};

/// The columns of comparison.csv, in order; comparison.md's tables show the marked ones in the
/// same order. Leads with the error against ground truth (aligned ATE, then RPE).
const std::vector<ComparisonColumn>& comparisonColumns();

void writeComparisonCsv(const std::string& path, const std::vector<ComparisonRow>& rows);
/// Markdown tables, with lines saying what the columns mean; when a reducer ran with several
/// seeds, also the mean ± std over its seeds of the columns marked over_seeds. Returns the text it
/// wrote.
std::string writeComparisonMarkdown(const std::string& path, const std::string& title,
                                    const std::vector<ComparisonRow>& rows);

}  // namespace budget_slam::report
