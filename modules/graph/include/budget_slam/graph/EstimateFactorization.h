#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/IncrementalOrdering.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// The factorization of H at a graph's estimate together with the graph state it was computed for,
/// as GTSAM's `Marginals` owns its factorization. Every covariance and information-gain query of
/// GraphBackend goes through it: it refactorizes on demand when the graph has changed since
/// (FactorGraph::revision(): any change of variables, factors or values), so no caller decides
/// whether a factor is current. The landmark marginals derived from it are kept with it.
///
/// A copy (GraphBackend::clone()) keeps the state it was computed for and the landmark marginals
/// but no CHOLMOD object: it refactorizes at its first query, with the same numbers.
class EstimateFactorization {
 public:
  /// `reorder_fill_ratio`: IncrementalOrdering's fresh-ordering bound
  /// (GraphSlamOptions::reorder_fill_ratio; 0: a fresh ordering at every structure change).
  explicit EstimateFactorization(double reorder_fill_ratio = 0);
  EstimateFactorization(const EstimateFactorization& other);
  EstimateFactorization& operator=(const EstimateFactorization&) = delete;

  /// True when a factorization of `graph` as it stands now was computed, here or in the object
  /// this one was copied from: an exact marginal now costs no more than the substitutions (after a
  /// copy, one refactorization).
  bool computedFor(const FactorGraph& graph) const;
  /// True when the CHOLMOD factor held here is that of `graph` as it stands now.
  bool isCurrent(const FactorGraph& graph) const;

  /// The Cholesky factor of H at `graph`'s current estimate (factorizeAtEstimate when not current).
  const SparseCholesky& factor(const FactorGraph& graph);
  /// Joint marginal covariance of `vars`, stacked in the order given (graph::jointMarginal).
  Eigen::MatrixXd jointMarginal(const FactorGraph& graph, const std::vector<VariableKey>& vars);
  /// Each variable's own marginal (graph::marginals).
  std::vector<Eigen::MatrixXd> marginals(const FactorGraph& graph,
                                         const std::vector<VariableKey>& vars);
  /// The 2x2 marginal of every landmark of `graph` (one shared substitution), kept until the
  /// graph changes.
  const std::map<LandmarkId, Eigen::Matrix2d>& landmarkMarginals(const FactorGraph& graph);
  /// One landmark's marginal: from landmarkMarginals() when they are of the current graph,
  /// otherwise on its own. Throws std::out_of_range for an unknown id.
  Eigen::Matrix2d landmarkMarginal(const FactorGraph& graph, LandmarkId id);

 private:
  IncrementalOrdering ordering_;
  SparseCholesky chol_;
  bool has_factor_ = false;     ///< chol_ holds a factor (never after a copy)
  bool computed_ = false;       ///< a factor was computed for revision_
  std::uint64_t revision_ = 0;  ///< FactorGraph::revision() it was computed for
  std::map<LandmarkId, Eigen::Matrix2d> landmark_cov_;
  bool has_landmark_cov_ = false;  ///< landmark_cov_ is of landmark_cov_revision_
  std::uint64_t landmark_cov_revision_ = 0;
};

}  // namespace budget_slam::graph
