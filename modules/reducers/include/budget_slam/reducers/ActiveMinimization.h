#pragma once
#include <string>
#include <vector>

#include "budget_slam/core/Reducer.h"

namespace budget_slam::reducers {

/// Choudhary et al. (ICRA 2015) Algorithm 3, active minimization, split into its parts so each
/// can be checked on its own (docs/ALGORITHMS.md "mi, objective mode").

/// One removal of the greedy sequence: the least informative remaining landmark (Alg. 4, ties to
/// the lowest id) and its information gain d just before it went [bits].
struct GreedyStep {
  LandmarkId id = kNoLandmarkId;
  double gain = 0;
};

/// Alg. 3 lines 3-14 run to exhaustion: removes every one of `candidates` from `scratch`, least
/// informative first, re-evaluating the gains after each removal. `scratch` is consumed.
std::vector<GreedyStep> greedySequence(Backend& scratch, std::vector<LandmarkId> candidates);

/// rho_k, k = 0..n, of Eq. 4 along a greedy sequence with gains d_1..d_n, over a map of
/// `n_landmarks` landmarks at the start:
///   rho_0 = lambda                         (Alg. 3 line 2: d = 0, m = 1)
///   rho_k = (1 - lambda) d_k / D + lambda (n_landmarks - k) / n_landmarks
/// with D = max_k d_k (the largest d over the whole sequence; D = 0 makes every d/D zero) and
/// negative round-off gains read as 0.
std::vector<double> objectiveValues(const std::vector<double>& gains, std::size_t n_landmarks,
                                    double lambda);

/// How many leading landmarks of the sequence Alg. 3 drops: up to the first k with
/// rho_k > rho_{k-1} (line 9, strict), or all of them.
std::size_t objectiveStop(const std::vector<double>& rho);

/// The alternative reading of Sec. IV-C ("until the objective function has reached its minimum
/// value", Fig. 3): the k of the smallest rho_k over the whole sequence (the first of equal
/// minima). Never fewer drops than objectiveStop(). [MutualInformationReducer] stop.
std::size_t objectiveMinimum(const std::vector<double>& rho);

/// Throws the ConfigError activeMinimization would throw on `ctx` for want of a faithful
/// look-ahead copy (called at the first step with landmarks, so the run fails early).
void checkLookAhead(const ScheduleContext& ctx, const std::string& mode);

/// Alg. 3 on ctx.backend as a plan for the BudgetManager.
/// - Candidates: the landmarks not seen in the last `pose_lag` steps (Sec. IV-C).
/// - Look-ahead copy: ctx.scratch() (the application's factory or Backend::clone()); when there
///   is none, a GaussianStateBackend snapshot of the backend (exact for the EKF; checked against
///   the backend's own gains, ConfigError naming `mode = <reason>` when they differ).
/// - The copy is first brought to its optimum Theta* (Backend::finish(); Alg. 5 line 5), then
///   the greedy sequence runs to exhaustion on it at that linearization point (Alg. 3 line 6:
///   Theta_r* = Theta_s* without L_o, no re-optimization in between).
/// - The plan drops the prefix before the first increase of rho, then marginalizes the poses
///   that see no kept landmark except the first and the last `pose_lag` (lines 15-16).
/// `global_minimum`: stop at objectiveMinimum() instead of objectiveStop().
ScheduledDrops activeMinimization(const ScheduleContext& ctx, double lambda, std::size_t pose_lag,
                                  const std::string& reason, bool global_minimum = false);

}  // namespace budget_slam::reducers
