#pragma once
#include <Eigen/Core>
#include <utility>

namespace budget_slam::gaussian {

/// Writes into `out` ((n-k) x (n-k), already sized) the square matrix `M` (n x n) without its
/// rows and columns [r, r+k): what dropping a variable's block does to a covariance (exact
/// marginalization of a Gaussian) or to an information matrix once the block is conditioned on.
/// Any Eigen dense expressions: Eigen matrices, or MRPT matrices' asEigen() maps.
template <class In, class Out>
void copyWithoutRowsCols(const In& M, Eigen::Index r, Eigen::Index k, Out&& out) {
  const Eigen::Index n = M.rows(), tail = n - r - k;
  out.topLeftCorner(r, r) = M.topLeftCorner(r, r);
  out.topRightCorner(r, tail) = M.topRightCorner(r, tail);
  out.bottomLeftCorner(tail, r) = M.bottomLeftCorner(tail, r);
  out.bottomRightCorner(tail, tail) = M.bottomRightCorner(tail, tail);
}

/// Writes into `out` (n-k entries, already sized) the vector `v` (n entries) without entries
/// [r, r+k): the mean's side of the same marginalization.
template <class In, class Out>
void copyWithoutEntries(const In& v, Eigen::Index r, Eigen::Index k, Out&& out) {
  const Eigen::Index tail = v.size() - r - k;
  out.head(r) = v.head(r);
  out.tail(tail) = v.tail(tail);
}

/// Deletes rows and columns [r, r+k) of a square matrix in place (copyWithoutRowsCols).
inline void eraseRowsCols(Eigen::MatrixXd& M, Eigen::Index r, Eigen::Index k) {
  Eigen::MatrixXd out(M.rows() - k, M.cols() - k);
  copyWithoutRowsCols(M, r, k, out);
  M = std::move(out);
}

}  // namespace budget_slam::gaussian
