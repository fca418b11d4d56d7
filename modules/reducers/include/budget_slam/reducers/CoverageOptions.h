#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/reducers/KMeans.h"

namespace budget_slam::reducers {

/// [CoverageReducer]: the clustering of Hochdorfer & Schlegel Sec. III-C, shared by `coverage`
/// and `coverage-mi` (docs/ALGORITHMS.md "coverage").
struct CoverageOptions : public TabledOptions<CoverageOptions> {
  static constexpr const char* kSection = "CoverageReducer";

  double cluster_ratio = 0.25;  ///< k = max(1, round(cluster_ratio * N)), N landmarks; in (0, 1]
                                ///< (paper: 1/4 of the landmarks, Sec. IV-A)
  KMeans::Distance distance = KMeans::Distance::L1;  ///< assignment metric: L1 (paper) or L2
  std::size_t max_iterations = 100;  ///< Lloyd iterations at most, >= 1 [iterations]
  /// Seed of the k-means++ start. Absent: the run's [LandmarkBudget] seed.
  std::uint64_t seed = 1;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<CoverageOptions>& table();
  /// The options of the KMeans for N landmarks.
  KMeans::Options kmeans(std::size_t n_points) const;
};

}  // namespace budget_slam::reducers
