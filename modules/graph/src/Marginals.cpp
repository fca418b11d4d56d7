#include "budget_slam/graph/Marginals.h"

namespace budget_slam::graph {

std::vector<int> columnsOf(const FactorGraph& graph, const std::vector<VariableKey>& vars) {
  std::vector<int> cols;
  for (const VariableKey& v : vars) {
    const int c = graph.column(v);
    for (std::size_t d = 0; d < v.dim(); ++d) cols.push_back(c + static_cast<int>(d));
  }
  return cols;
}

Eigen::MatrixXd jointMarginal(const FactorGraph& graph, const SparseCholesky& chol,
                              const std::vector<VariableKey>& vars) {
  return chol.inverseBlock(columnsOf(graph, vars));
}

std::vector<Eigen::MatrixXd> marginals(const FactorGraph& graph, const SparseCholesky& chol,
                                       const std::vector<VariableKey>& vars) {
  std::vector<std::vector<int>> groups;
  groups.reserve(vars.size());
  for (const VariableKey& v : vars) groups.push_back(columnsOf(graph, {v}));
  return chol.inverseDiagonalBlocks(groups);
}

}  // namespace budget_slam::graph
