#pragma once
#include <Eigen/Core>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// Marginal covariances under the Laplace approximation at the current estimate: the blocks of
/// H^-1, H being the information matrix the factorization `chol` was computed from
/// (factorizeAtEstimate). Blocks come from SparseCholesky::inverseBlock (forward substitutions
/// along elimination-tree paths), never from the full inverse.

/// The scalar columns of `vars`, stacked (3 a pose: x, y, yaw; 2 a landmark: x, y).
std::vector<int> columnsOf(const FactorGraph& graph, const std::vector<VariableKey>& vars);

/// Joint marginal covariance of `vars`, stacked in the order given.
Eigen::MatrixXd jointMarginal(const FactorGraph& graph, const SparseCholesky& chol,
                              const std::vector<VariableKey>& vars);

/// Each variable's own marginal (3x3 or 2x2), sharing one forward substitution.
std::vector<Eigen::MatrixXd> marginals(const FactorGraph& graph, const SparseCholesky& chol,
                                       const std::vector<VariableKey>& vars);

}  // namespace budget_slam::graph
