#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/IncrementalFactorization.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// The factorization of H at a graph's estimate, as GTSAM's `Marginals` owns its factorization:
/// every covariance and information-gain query of GraphBackend goes through it. It is the held
/// factor (IncrementalFactorization), which follows the graph's changes, so no caller decides
/// whether a factor is current: each query first folds in whatever changed since the last one
/// (rank updates where little changed, a refactorization where much did). The landmark marginals
/// derived from it are kept with it until the graph changes.
///
/// A copy (GraphBackend::clone()) copies the held factor; adopt() then ties it to the copy of the
/// graph.
class EstimateFactorization {
 public:
  /// `reorder_fill_ratio`: IncrementalFactorization's bound for a fresh ordering.
  explicit EstimateFactorization(double reorder_fill_ratio = 1.5);
  EstimateFactorization(const EstimateFactorization& other);
  EstimateFactorization& operator=(const EstimateFactorization&) = delete;

  /// This copy goes with `copy`, a copy of the graph the original followed (GraphBackend::clone()).
  void adopt(const FactorGraph& copy);
  /// True when the factor held here is that of `graph` as it stands now (no change to fold in): an
  /// exact marginal now costs only the substitutions.
  bool isCurrent(const FactorGraph& graph) const;

  /// The Cholesky factor of H at `graph`'s current estimate, its queries addressed by `graph`'s
  /// columns.
  /// `at_estimate`: IncrementalFactorization::factor's (every query below but the marked ones
  /// is at the estimate).
  const SparseCholesky& factor(const FactorGraph& graph, bool at_estimate = false);
  /// Joint marginal covariance of `vars`, stacked in the order given (graph::jointMarginal), at
  /// the estimate; with `at_estimate` false at the held factor's linearization point (at most one
  /// Gauss-Newton step behind: the latest pose's covariance after an update, the association
  /// gate), which costs no relinearization.
  Eigen::MatrixXd jointMarginal(const FactorGraph& graph, const std::vector<VariableKey>& vars,
                                bool at_estimate = true);
  /// Each variable's own marginal (graph::marginals), at the estimate.
  std::vector<Eigen::MatrixXd> marginals(const FactorGraph& graph,
                                         const std::vector<VariableKey>& vars);
  /// The 2x2 marginal of every landmark of `graph` (one shared substitution), kept until the
  /// graph changes.
  const std::map<LandmarkId, Eigen::Matrix2d>& landmarkMarginals(const FactorGraph& graph);
  /// One landmark's marginal: from landmarkMarginals() when they are of the current graph,
  /// otherwise on its own. Throws std::out_of_range for an unknown id.
  Eigen::Matrix2d landmarkMarginal(const FactorGraph& graph, LandmarkId id);

  /// The held factor itself: the backend's Gauss-Newton updates run on it.
  IncrementalFactorization& held() { return held_; }
  const IncrementalFactorization& held() const { return held_; }

 private:
  IncrementalFactorization held_;
  std::map<LandmarkId, Eigen::Matrix2d> landmark_cov_;
  bool has_landmark_cov_ = false;  ///< landmark_cov_ is of landmark_cov_revision_
  std::uint64_t landmark_cov_revision_ = 0;
  std::uint64_t landmark_cov_lineage_ = 0;
};

}  // namespace budget_slam::graph
