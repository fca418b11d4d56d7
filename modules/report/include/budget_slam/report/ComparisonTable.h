#pragma once
#include <limits>
#include <string>
#include <vector>

namespace budget_slam::report {

/// One run of `compare` (docs/OUTPUTS.md: comparison.csv / comparison.md). SI units; NaN where
/// a value does not apply (e.g. no ground truth): an empty field in the CSV, "-" in the table.
struct ComparisonRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string run;      ///< folder name: reference or the reducer's name
  std::string reducer;  ///< none for the reference
  std::string backend;
  std::string status;  ///< ok | failed | interrupted
  long long cap = -1;  ///< -1: no cap
  std::size_t landmarks = 0;
  double landmarks_reduction_pct = kNaN;  ///< 100 (1 - landmarks / reference landmarks)
  std::size_t poses = 0;
  double poses_reduction_pct = kNaN;
  std::size_t evictions = 0;
  double ate_m = kNaN, ale_m = kNaN, are_deg = kNaN, ud_pct = kNaN;
  double eig_min = kNaN, eig_max = kNaN;
  double gt_trajectory_rmse_m = kNaN, gt_trajectory_max_m = kNaN, gt_landmark_rmse_m = kNaN;
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

void writeComparisonCsv(const std::string& path, const std::vector<ComparisonRow>& rows);
/// Markdown table, with a line saying what the columns mean. Returns the text it wrote.
std::string writeComparisonMarkdown(const std::string& path, const std::string& title,
                                    const std::vector<ComparisonRow>& rows);

}  // namespace budget_slam::report
