#pragma once
// The held factor's L D L^T and its cost model (IncrementalFactorization, docs/GRAPH.md "Held
// factor", "Cost model"): what a change costs in place against a refactorization, and when the
// kept order has filled past its bound.
#include <cstdint>
#include <vector>

#include "HeldRecords.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph::held {

/// L's columns and elimination tree as CHOLMOD holds them (simplicial, rows ascending).
struct Tree {
  const int *p, *nz, *i;
  int n;
  int parent(int k) const { return nz[k] > 1 ? i[p[k] + 1] : -1; }
};

/// CHOLMOD's simplicial L D L^T of the held H (factorized in the order H's rows stand) and the
/// measures the cost model reads.
/// Invariants (between updates): L D L^T = H as HeldMatrix holds it, to rounding; `path_cost`
/// is of L as it stood at the last factorization or pattern cut; `stale_pattern` is set while L
/// holds entries a factorization of H would not have.
struct HeldCholesky {
  SparseCholesky chol;
  bool map_valid = false;
  std::uint64_t map_variables = 0;  ///< FactorGraph::variablesVersion() of the column map
  double fresh_fill = 0;            ///< nnz(L) per used row right after the last fresh ordering
  double fresh_flops = 0;      ///< factorization flops per used row after the last fresh ordering
  double fresh_depth = 0;      ///< meanDepth() after the last fresh ordering
  double refresh_flops = 0;    ///< flops of the last numeric factorization
  bool stale_pattern = false;  ///< L holds entries a factorization of H would not have
  /// Entries of L on the etree path from every position to the root, as L stood at the last
  /// factorization (cost model estimates before the exact walk of pathEntries).
  std::vector<double> path_cost;

  HeldCholesky() = default;
  HeldCholesky(const HeldCholesky& o);
  HeldCholesky& operator=(const HeldCholesky&) = delete;

  Tree tree();
  double nonZerosOfL();
  void computePathCosts();
  /// Mean depth of the rows of live variables (owner >= 0) in L's elimination tree: the length
  /// of the paths every partial inverse walks (the variables placed last since the last fresh
  /// ordering lie on all of them).
  double meanDepth(const std::vector<int>& owner);
  /// The cost-model bound on in-place work: that of a numeric refactorization of an H with
  /// `h_entries` stored entries, in entries of L.
  double refreshCap(std::size_t h_entries) const;
  /// Flops of re-eliminating rows `first` .. n-1 of L as its pattern stands (CHOLMOD's row
  /// factorization: about (entries of a column)^2 per column, for the entries in those rows):
  /// a partial refactorization's work; flopsFrom(0) estimates a whole one.
  double flopsFrom(int first);
  /// The cost-model bound of a partial refactorization from row `first` of an H whose trailing
  /// columns hold `h_entries` entries, in entries of L (refreshCap's units). The trailing
  /// columns are counted first; the scan stops once above `stop` (then a lower bound).
  double partialCap(int first, std::size_t h_entries, double stop);
  /// Entries of L on the etree path from position k to the root (the work of a rank-1 change
  /// that starts there), stopping once above `cap`.
  double pathEntries(int k, double cap);
  /// The pieces' rows as columns of C (H +-= C C^T), rows ascending; rows in `deleted` left
  /// out. Returns the work of the columns by the cost model (stopping once above `cap`).
  double columns(const std::vector<Piece>& pieces, const std::vector<char>& deleted,
                 std::vector<int>* cp, std::vector<int>* ci, std::vector<double>* cx, double cap);
  /// The fill per row (nnz(L), or the flops of the last factorization) past `ratio` times the
  /// one right after the last fresh ordering; also when a tenth of the rows belong to removed
  /// variables (their places in the kept order no longer fit the graph: mass pose
  /// marginalization, a bounded graph's window). `used_rows`: rows placed so far, `dead_rows`:
  /// those of removed variables.
  bool degraded(double ratio, int used_rows, int dead_rows);
};

/// Cost model of a change (docs/GRAPH.md "Held factor"): CHOLMOD's rank-1 update or downdate
/// touches every entry of L on the elimination-tree path from its first row to the root; a
/// numeric refactorization does the flops of the factorization and reads H. Per unit, measured
/// on the machine of docs/PERFORMANCE.md; only the ratio matters, the cheaper way is taken.
constexpr double kUpdateCostPerEntry = 2.5;  ///< [ns] per entry of L on a rank-1 path
constexpr double kRefreshCostPerFlop = 0.7;  ///< [ns] per flop of the simplicial factorization
constexpr double kRefreshCostPerEntry = 20;  ///< [ns] per entry of H

}  // namespace budget_slam::graph::held
