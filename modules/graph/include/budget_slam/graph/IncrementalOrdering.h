#pragma once
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph {

/// Keeps the fill-reducing ordering of the graph's variables between factorizations while the
/// structure only grows (docs/GRAPH.md "Incremental solving"). CHOLMOD's fresh analysis (AMD,
/// then METIS when AMD fills much) is the costliest part of a factorization of a long chain of
/// poses; here it runs only when the fill of the kept ordering grows too large:
///
/// * same structure as the last call: numeric refactorization only (SparseCholesky::refactorize);
/// * the structure changed: the kept variables stay in their elimination order, removed ones
///   leave, new ones are eliminated last (new landmarks, then new poses: the latest pose is
///   connected to every new factor), as iSAM does; CHOLMOD is given that ordering;
/// * the fill ratio nnz(L) / nnz(tril H) exceeds `refresh_fill` times the one of the last fresh
///   analysis: a fresh analysis, whose ordering is kept from then on.
///
/// The factor is the same matrix whatever the ordering, so results differ only by rounding.
class IncrementalOrdering {
 public:
  /// refresh_fill <= 0: a fresh analysis at every structure change (the batch path).
  explicit IncrementalOrdering(double refresh_fill = 1.5) : refresh_fill_(refresh_fill) {}

  /// Factorizes H, linearized from `graph` (its current structure and column layout), into
  /// `chol`. Returns false when H is not positive definite. `chol` must be used only through
  /// this object between calls (it relies on the analysis it left there).
  bool factorize(const FactorGraph& graph, const Eigen::SparseMatrix<double>& H,
                 SparseCholesky* chol);

  std::size_t freshAnalyses() const { return fresh_; }
  std::size_t reusedAnalyses() const { return reused_; }
  double refreshFill() const { return refresh_fill_; }

 private:
  bool fresh(const FactorGraph& graph, const Eigen::SparseMatrix<double>& H, SparseCholesky* chol);

  double refresh_fill_;
  std::vector<VariableKey> order_;  ///< elimination order of the variables at version_
  std::uint64_t version_ = 0;       ///< structure version the factor in the last chol has
  const SparseCholesky* chol_ = nullptr;
  double fresh_ratio_ = 0;  ///< nnz(L) / nnz(tril H) of the last fresh analysis
  std::size_t fresh_ = 0, reused_ = 0;
};

}  // namespace budget_slam::graph
