#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::metrics {

/// [Metrics]: limits of the comparison against the reference run.
struct MetricsOptions : public TabledOptions<MetricsOptions> {
  static constexpr const char* kSection = "Metrics";

  /// EIG needs the eigenvalues of a dense covariance difference (O(n^3)); above this many rows it
  /// is skipped and reported empty [rows]. Default: 3000 (about 1500 landmarks or 1000 poses).
  std::size_t eig_max_rows = 3000;
  /// k of the relocalization coverage: a step is covered when the robot observed at least this
  /// many landmarks of the map there (two range-bearing sightings fix a 2D pose) [landmarks].
  /// Default: 2.
  std::size_t reloc_min_landmarks = 2;
  /// Rawlogs without sensor IDs: a final-map landmark stands for the reference run's landmark it
  /// pairs with when their squared Mahalanobis distance (summed covariances) is at most this.
  /// Default: 13.8155 (chi-square, 2 degrees of freedom, 99.9%).
  double reloc_match_chi2 = 13.8155;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<MetricsOptions>& table();
};

}  // namespace budget_slam::metrics
