#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "budget_slam/core/Ids.h"

namespace budget_slam::reducers {

/// What one place tells about the landmarks read from it: for each landmark l, I_l(p), the
/// Fisher information of its readings from p about the robot pose (x, y, yaw), the mean over
/// those readings (docs/ALGORITHMS.md "localization-information") [1/m^2, 1/(m rad), 1/rad^2].
struct PlaceReadings {
  std::vector<LandmarkId> ids;        ///< distinct
  std::vector<Eigen::Matrix3d> info;  ///< info[i] belongs to ids[i]
};

/// A cap-sized subset of landmarks and its value under the place objective.
struct LogDetSelection {
  std::vector<LandmarkId> selection;  ///< sorted
  double objective = 0;  ///< F(S) = sum_p log det (Lambda_0 + sum_{l in S} I_l(p)) [nats]
  double gain = 0;       ///< F(S) - F(empty set) [nats] (>= 0; the normalized objective)
};

/// F(S) of `selection` over `places` with the prior `prior` (Lambda_0, positive definite).
double logDetObjective(const std::vector<PlaceReadings>& places, const Eigen::Matrix3d& prior,
                       const std::vector<LandmarkId>& selection);

/// Greedy insertion on F (Nemhauser, Wolsey & Fisher 1978): from the empty set, `k` times the
/// candidate of the largest gain F(S + l) - F(S) joins, ties to the lowest id. F is monotone
/// submodular (log det is concave on positive definite matrices and every I_l(p) is positive
/// semidefinite), so the result's gain is >= (1 - 1/e) of the best k-subset's. Candidates read
/// from no place have no gain and fill the set last, lowest id first. k >= |candidates| keeps
/// them all. Readings of landmarks that are not candidates are ignored.
LogDetSelection greedyLogDetSelection(const std::vector<PlaceReadings>& places,
                                      const Eigen::Matrix3d& prior,
                                      std::vector<LandmarkId> candidates, std::size_t k);

/// The best k-subset of `candidates` by exhaustive enumeration (the reference of the greedy one
/// in tests): ties to the lexicographically smallest sorted set. Throws std::length_error when
/// there are more than `max_subsets` subsets to try.
LogDetSelection exhaustiveLogDetSelection(const std::vector<PlaceReadings>& places,
                                          const Eigen::Matrix3d& prior,
                                          std::vector<LandmarkId> candidates, std::size_t k,
                                          std::size_t max_subsets = 2000000);

}  // namespace budget_slam::reducers
