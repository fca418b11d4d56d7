#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

struct cholmod_factor_struct;

namespace budget_slam::graph {

/// One column of a sparse right-hand side: values on up to 3 scalar indices of H, all of one
/// variable (a pose's x, y, yaw or a landmark's x, y; such indices lie on one elimination-tree
/// path).
struct SparseColumn {
  int n = 0;
  std::array<int, 3> idx{};
  std::array<double, 3> val{};
};

/// Sparse Cholesky factorization P H P^T = L L^T (or L D L^T) of a symmetric positive definite H,
/// by CHOLMOD. Besides solves and log-determinants it gives blocks of H^-1 without forming the
/// inverse (inverseBlock, inverseGram).
///
/// Two ways in: factorize() lets CHOLMOD choose the fill-reducing ordering (AMD or METIS) and
/// the form (simplicial or supernodal), for batch solves; factorizeInOrder() takes H already
/// ordered and keeps a simplicial L D L^T, the form CHOLMOD's update/downdate routines modify in
/// place (updateInPlace, deleteRowInPlace, pruneToPattern: IncrementalFactorization). The
/// partial inverses read either form in place.
///
/// The queries (inverseBlock, inverseQuadraticForm, inverseGram, inverseDiagonalBlocks) address
/// columns of H; with setColumnMap they address external columns instead, each mapped to a row
/// of the factorized matrix (the held factorization keeps each variable in rows of its own,
/// while the graph's column layout moves with every new variable).
class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  /// A deep copy of the factor (cholmod_copy_factor); the query caches are rebuilt lazily.
  SparseCholesky copy() const;

  /// Factorizes H (only its lower triangle is read). The symbolic analysis (ordering) is reused
  /// when `pattern_version` equals the previous call's and is not 0 (0: always analyse).
  /// With `variable_starts` (the first column of each variable, then the size of H;
  /// FactorGraph::variableStarts) the ordering is AMD on the variable graph, each variable's
  /// columns kept together; CHOLMOD's own choice (AMD on the scalars, or METIS) otherwise, and
  /// whenever the variable ordering fills much (CHOLMOD's rule for trying METIS).
  /// Returns false when H is not positive definite.
  bool factorize(const Eigen::SparseMatrix<double>& H, std::uint64_t pattern_version = 0,
                 const std::vector<int>* variable_starts = nullptr);
  /// The upper triangle of a symmetric matrix in compressed columns (column c holds its rows
  /// r <= c, ascending): a view of the caller's arrays.
  struct UpperTriangle {
    int n = 0;
    const int* p = nullptr;  ///< n + 1 column starts
    const int* i = nullptr;
    const double* x = nullptr;
  };
  /// Analyses and factorizes H in the order its rows stand (no fill-reducing permutation: the
  /// caller has ordered them), as a simplicial L D L^T, the form CHOLMOD's update routines modify
  /// in place (updateInPlace, deleteRowInPlace). Returns false when H is not positive definite.
  bool factorizeInOrder(const UpperTriangle& H);
  /// Numeric refactorization of H, in the same order, into the factor as it stands: its storage
  /// and pattern are kept (after in-place updates too, which CHOLMOD's simplicial factorization
  /// accepts), no analysis and no permutation. Throws std::logic_error without a prior
  /// factorizeInOrder; returns false when H is not positive definite.
  bool refactorizeInOrder(const UpperTriangle& H);
  /// Partial re-elimination: rows `first` .. n-1 of L (and of D) computed again from H, rows
  /// above kept (CHOLMOD's incremental cholmod_rowfac), in the kept order. Valid when only
  /// columns `first` .. n-1 of H (its upper triangle) changed since L was L D L^T = H: row k of
  /// L depends only on H's columns up to k. The work is that of the rows re-eliminated (the
  /// trailing block and its entries in the leading columns), not of the whole factor. Throws
  /// std::logic_error without a prior factorizeInOrder; false when H is not positive definite.
  bool refactorizeTrailing(const UpperTriangle& H, int first);
  /// A fill-reducing ordering of a symmetric pattern on n nodes (a graph's variables), given by
  /// its strict upper triangle (column c's rows r < c, sorted): AMD, postordered so every
  /// elimination subtree is contiguous. order[k] = the node eliminated k-th. No factorization.
  /// With `group` (one entry per node, >= 0): constrained AMD (CAMD), every node of a group
  /// after those of the lower groups (iSAM2's constrained ordering: the variables the next
  /// changes touch last), not postordered.
  std::vector<int> orderNodes(int n, const std::vector<int>& p, const std::vector<int>& i,
                              const std::vector<int>* group = nullptr);
  /// Non-zeros of L predicted by the last symbolic analysis (CHOLMOD's lnz; no extraction).
  double analysedNonZeros() const;
  /// Floating-point operations of the numeric factorization the last analysis predicts (CHOLMOD's
  /// fl).
  double analysedFlops() const;
  /// The queries' external column c is row rows[c] of the factorized matrix from now on (kept
  /// across refactorizations; empty: the identity).
  void setColumnMap(std::vector<int> rows);
  /// The fill-reducing ordering in use: perm[k] = the column of H eliminated k-th.
  std::vector<int> ordering() const;
  bool ok() const;
  int size() const;

  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// ln det(H).
  double logDet() const;
  /// Non-zeros of L (fill), for reports.
  std::size_t factorNonZeros() const;

  /// (H^-1)_{S,S} for the scalar indices S (in H's own ordering), stacked in the order given.
  /// With Y = L^-1 P E_S, H^-1 = P^T L^-T L^-1 P gives (H^-1)_{S,S} = Y^T Y. Column k of Y is
  /// non-zero only on the path from k to the root of the elimination tree (Gilbert & Peierls),
  /// so only forward substitutions along those paths are done: no backward solve, no inverse.
  Eigen::MatrixXd inverseBlock(const std::vector<int>& S) const;
  /// W (H^-1)_{S,S} W^T for a dense W (r x |S|), from Y = L^-1 P E_S W^T: one forward
  /// substitution with r right-hand sides instead of |S| (information gain, low-rank U = W^T W).
  Eigen::MatrixXd inverseQuadraticForm(const std::vector<int>& S, const Eigen::MatrixXd& W) const;
  /// R^T H^-1 R for a sparse R (n x r) given by its columns (one variable each), from
  /// Y = L^-1 P R: column j of Y is non-zero only on the etree path of its variable, so with the
  /// columns sorted by the postorder of their first node, row a of Y is non-zero only on the
  /// contiguous range of columns whose node lies in a's subtree. The forward substitution and
  /// the Gram product Y^T Y run on those ranges only (Choudhary et al.'s information gain:
  /// R = A_B^T, the whitened pose Jacobians of a landmark's sightings). The rows of the dense
  /// root separator at the end of every path (the factor's last columns when they form a full
  /// triangle) are done by dense kernels instead: Y_T = L_TT^-1 Z_T and Y_T^T Y_T.
  /// Returns the LOWER triangle of the r x r result with its rows and columns in sorted order:
  /// (*order)[p] = the caller's column at position p. A view of a per-thread workspace, valid
  /// until the thread's next query on any SparseCholesky (a SparseCholesky itself is not
  /// thread-safe).
  Eigen::Map<const Eigen::MatrixXd> inverseGram(const std::vector<SparseColumn>& cols,
                                                std::vector<int>* order) const;
  /// The diagonal blocks (H^-1)_{S_g,S_g} of several index groups, sharing one forward
  /// substitution (for e.g. every landmark's 2x2 marginal at once).
  std::vector<Eigen::MatrixXd> inverseDiagonalBlocks(
      const std::vector<std::vector<int>>& groups) const;

  // -- in-place modification of a factorizeInOrder() factor (IncrementalFactorization) --
  /// L D L^T +- C C^T (CHOLMOD's updown) for C given by columns: column j's rows
  /// i[p[j] .. p[j+1]), ascending, in the factor's order (it applies no permutation), values x.
  /// False when a downdate loses definiteness (the factor is then to be refactorized).
  bool updateInPlace(bool update, const std::vector<int>& p, const std::vector<int>& i,
                     const std::vector<double>& x);
  /// Row and column k become those of the identity (CHOLMOD's rowdel). False on failure.
  bool deleteRowInPlace(int k);
  /// L's pattern cut to that of a factorization of H (CHOLMOD's resymbol): the entries that
  /// downdates and row deletions leave as zeros go. No flops. False on failure.
  bool pruneToPattern(const UpperTriangle& H);
  /// Flops of the last numeric factorization (CHOLMOD's rowfacfl).
  double lastFactorizationFlops() const;
  /// CHOLMOD's factor, read-only use (its elimination tree for cost estimates).
  cholmod_factor_struct* factor();
  /// Position of the factorized matrix's row `row` in the factor's ordering (P^-1).
  int position(int row) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace budget_slam::graph
