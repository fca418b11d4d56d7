#pragma once
#include <vector>

#include "budget_slam/core/Reducer.h"
#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/reducers/KMeans.h"

namespace budget_slam::reducers {

/// The coverage clusters (Hochdorfer & Schlegel Sec. III-B/C): k-means over the running means of
/// the observation positions (LandmarkView::obs_mean, their Eq. 1-2) of every landmark in the
/// map, protected or not, k = max(1, round(cluster_ratio * N)). label[i] is landmarks[i]'s.
KMeans::Result coverageClusters(const std::vector<LandmarkView>& landmarks,
                                const CoverageOptions& options);

/// How a cluster's spread is measured from the per-landmark usefulness s.
enum class Spread {
  /// max s - min s over every member: Hochdorfer & Schlegel Eq. 5.
  Members,
  /// max s over every member - min s over the cluster's candidates: the gap between the best
  /// landmark that stays in the region and the one that would go (coverage-mi).
  BestMemberOverWorstCandidate,
};

/// What pickByClusterSpread decided.
struct ClusterPick {
  LandmarkId id = kNoLandmarkId;
  double score = 0;         ///< s of the dropped landmark
  std::size_t cluster = 0;  ///< its cluster
  double spread = 0;        ///< that cluster's spread
};

/// Hochdorfer & Schlegel Sec. III-E with usefulness `s` (one per ctx.landmarks entry, higher =
/// more useful): among the clusters holding at least one candidate, the one with the largest
/// spread; in it, the candidate with the lowest s. Ties between clusters go to the one whose
/// pick has the lowest s, then the lowest id; ties within a cluster to the lowest id.
ClusterPick pickByClusterSpread(const DropContext& ctx, const std::vector<std::size_t>& label,
                                const std::vector<double>& s, Spread spread);

}  // namespace budget_slam::reducers
