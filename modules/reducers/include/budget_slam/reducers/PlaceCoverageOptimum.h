#pragma once
#include <cstddef>
#include <vector>

#include "budget_slam/core/Ids.h"

namespace budget_slam::reducers {

/// The best place coverage any selection of `budget` landmarks can give, with hindsight:
///   max f(S) = sum over places p of min(k, |S observed from p|)  subject to  |S| <= budget,
/// the objective of `place-coverage` (docs/ALGORITHMS.md "place-coverage"), solved exactly as an
/// integer program with GLPK's branch and cut:
///   max sum_p y_p  s.t.  y_p <= sum_{L seen from p} x_L,  0 <= y_p <= k,  sum_L x_L <= budget,
///   x_L in {0, 1}
/// (y_p may stay continuous: for integer x its optimum is integer).
struct PlaceCoverageOptimum {
  double coverage = 0;                ///< f of the best selection [places, counting up to k each]
  std::vector<LandmarkId> selection;  ///< the landmarks of one best selection, sorted
  bool proven_optimal = true;         ///< false when GLPK stopped at its time limit (then a
                                      ///< feasible selection and `coverage` its value)
  double upper_bound = 0;             ///< GLPK's bound: `coverage` <= optimum <= upper_bound
};

struct PlaceCoverageOptimumLimits {
  std::size_t max_sightings = 2000000;  ///< (place, landmark) pairs at most: the matrix size
  double time_limit_s = 60;             ///< branch and cut time limit [s]
};

/// `places[p]`: the landmark ids observed from place p (duplicates ignored). Throws
/// std::length_error, naming the size and the limit, when the problem has more sightings than
/// `limits.max_sightings`; std::runtime_error when GLPK fails.
PlaceCoverageOptimum solvePlaceCoverageOptimum(const std::vector<std::vector<LandmarkId>>& places,
                                               std::size_t k, std::size_t budget,
                                               const PlaceCoverageOptimumLimits& limits = {});

}  // namespace budget_slam::reducers
