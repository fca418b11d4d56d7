#pragma once
#include <string>

#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// Nonlinear least squares on the graph (Choudhary et al. Eq. 3) by Gauss-Newton or
/// Levenberg-Marquardt on the sparse normal equations H dx = -g.
struct SolverSettings {
  enum class Method { GaussNewton, LevenbergMarquardt };
  Method method = Method::GaussNewton;
  int max_iterations = 50;
  /// Converged when max |dx| falls below this (m and rad alike).
  double step_tolerance = 1e-10;
  /// ...or when chi2 decreases by less than this fraction (0: off; Gauss-Newton also stops when
  /// a step raises chi2, i.e. at the rounding floor of the cost).
  double relative_chi2_tolerance = 0;
  /// Levenberg-Marquardt: initial damping lambda, added as lambda * diag(H) (Marquardt scaling).
  double lm_initial_lambda = 1e-5;
  double lm_lambda_factor =
      10.0;  ///< lambda multiplier on a rejected / divisor on an accepted step
  /// Poll budget_slam::Cancellation before every iteration and throw Interrupted on a stop
  /// request (Ctrl-C); the estimate is then the last accepted iterate. For the full solves, whose
  /// iterations on a large graph add up to seconds.
  bool stop_on_request = false;
};

struct SolveReport {
  int iterations = 0;
  double initial_chi2 = 0;
  double final_chi2 = 0;
  double last_step_norm = 0;  ///< max |dx| of the last accepted step
  bool converged = false;
};

/// Iterates from the graph's current estimate, updating it in place, every iteration on H
/// linearized and factorized afresh: the batch solver (the reference the held factor is tested
/// against, and the backend's Levenberg-Marquardt solves). `chol` keeps CHOLMOD's analysis
/// between calls while the graph's structure is unchanged; on return it holds a factorization of
/// H at the last linearization point but one (call factorizeAtEstimate for marginals at the
/// final estimate). Throws std::runtime_error if H is not positive definite (an unconstrained
/// variable).
SolveReport optimize(FactorGraph& graph, const SolverSettings& s, SparseCholesky* chol);

/// Factorizes H at the current estimate from scratch (no update): the batch counterpart of the
/// held factor's queries.
void factorizeAtEstimate(const FactorGraph& graph, SparseCholesky* chol);

}  // namespace budget_slam::graph
