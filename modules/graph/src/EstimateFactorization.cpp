#include "budget_slam/graph/EstimateFactorization.h"

#include "budget_slam/graph/Marginals.h"

namespace budget_slam::graph {

EstimateFactorization::EstimateFactorization(double reorder_fill_ratio)
    : held_(HeldFactorParams{reorder_fill_ratio}) {}

EstimateFactorization::EstimateFactorization(const EstimateFactorization& o)
    : held_(o.held_),
      landmark_cov_(o.landmark_cov_),
      has_landmark_cov_(o.has_landmark_cov_),
      landmark_cov_revision_(o.landmark_cov_revision_),
      landmark_cov_lineage_(o.landmark_cov_lineage_) {}

void EstimateFactorization::adopt(const FactorGraph& copy) {
  held_.adopt(copy);
  landmark_cov_lineage_ = copy.lineage();
}

bool EstimateFactorization::isCurrent(const FactorGraph& graph) const {
  return held_.isCurrent(graph);
}

const SparseCholesky& EstimateFactorization::factor(const FactorGraph& graph, bool at_estimate) {
  return held_.factor(graph, at_estimate);
}

Eigen::MatrixXd EstimateFactorization::jointMarginal(const FactorGraph& graph,
                                                     const std::vector<VariableKey>& vars,
                                                     bool at_estimate) {
  return graph::jointMarginal(graph, factor(graph, at_estimate), vars);
}

std::vector<Eigen::MatrixXd> EstimateFactorization::marginals(
    const FactorGraph& graph, const std::vector<VariableKey>& vars) {
  return graph::marginals(graph, factor(graph, /*at_estimate=*/true), vars);
}

const std::map<LandmarkId, Eigen::Matrix2d>& EstimateFactorization::landmarkMarginals(
    const FactorGraph& graph) {
  if (!has_landmark_cov_ || landmark_cov_revision_ != graph.revision() ||
      landmark_cov_lineage_ != graph.lineage()) {
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
    landmark_cov_lineage_ = graph.lineage();
  }
  return landmark_cov_;
}

Eigen::Matrix2d EstimateFactorization::landmarkMarginal(const FactorGraph& graph, LandmarkId id) {
  if (has_landmark_cov_ && landmark_cov_revision_ == graph.revision() &&
      landmark_cov_lineage_ == graph.lineage())
    return landmark_cov_.at(id);
  return jointMarginal(graph, {VariableKey::landmark(id)});
}

}  // namespace budget_slam::graph
