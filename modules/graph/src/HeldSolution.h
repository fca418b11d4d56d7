#pragma once
// The held factor's solution dx = -H^-1 g, kept between updates and solved again only where it
// changed: iSAM2's partial back-substitution ("wildfire", Kaess et al. 2012) on the held
// L D L^T (IncrementalFactorization, docs/GRAPH.md "Partial back-substitution").
#include <Eigen/Core>
#include <vector>

struct cholmod_factor_struct;

namespace budget_slam::graph::held {

/// dx = -H^-1 g from CHOLMOD's simplicial factor of H (in the order H's rows stand, P = I),
/// with y = L^-1 (-g) (the forward substitution) kept beside it.
///
/// Why a change needs only part of it: every change of H, g and L since the last solve lies in
/// rows and columns >= `from` (the first row any change touched: IncrementalFactorization's
/// first changed row of each fold). L's leading columns (< from) and D's leading entries then
/// stay what they were (row k of L depends on H's columns up to k, and H's entries between a
/// leading and a trailing row did not change), so
///  * y's leading rows stay; its trailing rows are solved again (from the leading columns'
///    entries in trailing rows and the trailing columns);
///  * dx's trailing rows are solved again; a leading row k changes only through the rows below
///    it in its column of L, all on its elimination-tree path. Row k is solved again when one
///    of them "propagated" (moved by more than `threshold` since its dependants were last
///    solved); a row whose etree parent was not solved again is skipped with its whole subtree
///    (column k's pattern minus its parent lies in its parent's pattern).
/// A row that propagates records its value (`seen`), so a row skipped by the threshold never
/// lags a row of its column by more than twice the threshold, however many solves pass (iSAM2
/// compares with the last value instead, so sub-threshold moves can add up).
///
/// Invariants between solves: y = L^-1 (-g) and dx = -H^-1 g for the L and g of the last solve,
/// exactly when every solve since the last whole one had threshold 0, otherwise rows skipped
/// keep their last value (a solve with a threshold below an earlier one's solves every row);
/// `from` is the first row of L or g changed since (n: none, 0: all, after a fresh ordering or a
/// whole refactorization).
struct HeldSolution {
  Eigen::VectorXd y;     ///< L^-1 (-g), by row (D not applied)
  Eigen::VectorXd dx;    ///< the solution, by row
  Eigen::VectorXd seen;  ///< each row's value when its dependants were last solved with it
  int from = 0;          ///< first row changed since the last solve
  /// Rows solved again by the last solve, descending.
  std::vector<int> rows;

  /// Everything changed (a fresh ordering, a whole refactorization, a pattern cut).
  void invalidate() { from = 0; }
  /// L and g changed in rows `row` .. n-1 only.
  void changedFrom(int row) { from = from < row ? from : row; }
  /// Solves again the rows that changed (all when `from` is 0 or the size changed).
  /// `threshold` [m, rad]: a row's change below it does not propagate (0: every change).
  void solve(const cholmod_factor_struct& L, const Eigen::VectorXd& g, double threshold);

 private:
  std::vector<char> recalc_, propagates_;
  double lag_ = 0;  ///< the largest threshold since the last solve of every row [m, rad]
};

}  // namespace budget_slam::graph::held
