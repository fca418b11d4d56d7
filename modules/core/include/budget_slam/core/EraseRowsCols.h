#pragma once
#include <Eigen/Core>
#include <utility>

namespace budget_slam {

/// Deletes rows and columns [r, r+k) of a square matrix: what dropping a landmark's block does
/// to a covariance or information matrix (exact marginalization of a Gaussian's covariance).
inline void eraseRowsCols(Eigen::MatrixXd& M, Eigen::Index r, Eigen::Index k) {
  const Eigen::Index n = M.rows(), tail = n - r - k;
  Eigen::MatrixXd out(n - k, n - k);
  out.topLeftCorner(r, r) = M.topLeftCorner(r, r);
  out.topRightCorner(r, tail) = M.topRightCorner(r, tail);
  out.bottomLeftCorner(tail, r) = M.bottomLeftCorner(tail, r);
  out.bottomRightCorner(tail, tail) = M.bottomRightCorner(tail, tail);
  M = std::move(out);
}

}  // namespace budget_slam
