#include "budget_slam/graph/EstimateFactorization.h"

#include "budget_slam/graph/Marginals.h"
#include "budget_slam/graph/Solver.h"

namespace budget_slam::graph {

EstimateFactorization::EstimateFactorization(double reorder_fill_ratio)
    : ordering_(reorder_fill_ratio) {}

EstimateFactorization::EstimateFactorization(const EstimateFactorization& o)
    : ordering_(o.ordering_.refreshFill()),  // CHOLMOD objects are never shared: no factor yet
      computed_(o.computed_),
      revision_(o.revision_),
      landmark_cov_(o.landmark_cov_),
      has_landmark_cov_(o.has_landmark_cov_),
      landmark_cov_revision_(o.landmark_cov_revision_) {}

bool EstimateFactorization::computedFor(const FactorGraph& graph) const {
  return computed_ && revision_ == graph.revision();
}

bool EstimateFactorization::isCurrent(const FactorGraph& graph) const {
  return has_factor_ && computedFor(graph);
}

const SparseCholesky& EstimateFactorization::factor(const FactorGraph& graph) {
  if (!isCurrent(graph)) {
    has_factor_ = false;  // a throw below (H not positive definite) leaves no factor
    factorizeAtEstimate(graph, &chol_, &ordering_);
    has_factor_ = computed_ = true;
    revision_ = graph.revision();
  }
  return chol_;
}

Eigen::MatrixXd EstimateFactorization::jointMarginal(const FactorGraph& graph,
                                                     const std::vector<VariableKey>& vars) {
  return graph::jointMarginal(graph, factor(graph), vars);
}

std::vector<Eigen::MatrixXd> EstimateFactorization::marginals(
    const FactorGraph& graph, const std::vector<VariableKey>& vars) {
  return graph::marginals(graph, factor(graph), vars);
}

const std::map<LandmarkId, Eigen::Matrix2d>& EstimateFactorization::landmarkMarginals(
    const FactorGraph& graph) {
  if (!has_landmark_cov_ || landmark_cov_revision_ != graph.revision()) {
    std::vector<VariableKey> vars;
    vars.reserve(graph.landmarks().size());
    for (const auto& [id, l] : graph.landmarks()) vars.push_back(VariableKey::landmark(id));
    landmark_cov_.clear();
    if (!vars.empty()) {
      const std::vector<Eigen::MatrixXd> m = marginals(graph, vars);
      for (std::size_t k = 0; k < vars.size(); ++k) landmark_cov_[vars[k].id] = m[k];
    }
    has_landmark_cov_ = true;
    landmark_cov_revision_ = graph.revision();
  }
  return landmark_cov_;
}

Eigen::Matrix2d EstimateFactorization::landmarkMarginal(const FactorGraph& graph, LandmarkId id) {
  if (has_landmark_cov_ && landmark_cov_revision_ == graph.revision()) return landmark_cov_.at(id);
  return jointMarginal(graph, {VariableKey::landmark(id)});
}

}  // namespace budget_slam::graph
