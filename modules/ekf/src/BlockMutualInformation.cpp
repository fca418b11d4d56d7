#include "budget_slam/ekf/BlockMutualInformation.h"

#include "budget_slam/core/EraseRowsCols.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace budget_slam::ekf {

BlockMutualInformation::BlockMutualInformation(const Eigen::MatrixXd& P) : P_(P) {
  const Eigen::Index n = P.rows();
  const double max_diag = n > 0 ? P.diagonal().maxCoeff() : 0.0;
  lambda_row_.assign(static_cast<std::size_t>(n), -1);
  std::vector<Eigen::Index> active;
  for (Eigen::Index i = 0; i < n; ++i)
    if (P(i, i) > 1e-15 * max_diag) {
      lambda_row_[static_cast<std::size_t>(i)] = static_cast<long>(active.size());
      active.push_back(i);
    }
  const Eigen::Index m = static_cast<Eigen::Index>(active.size());
  Eigen::MatrixXd Pa(m, m);
  for (Eigen::Index r = 0; r < m; ++r)
    for (Eigen::Index c = 0; c < m; ++c) Pa(r, c) = P(active[r], active[c]);

  Eigen::LLT<Eigen::MatrixXd> llt(Pa);
  if (llt.info() != Eigen::Success) {
    // Round-off can leave an EKF covariance a hair from positive definite; a relative jitter far
    // below any physical variance restores the factorization.
    Pa.diagonal().array() += 1e-12 * Pa.diagonal().mean();
    llt.compute(Pa);
    if (llt.info() != Eigen::Success) throw NotPositiveDefinite();
  }
  lambda_ = llt.solve(Eigen::MatrixXd::Identity(m, m));
  lambda_ = 0.5 * (lambda_ + lambda_.transpose()).eval();
}

double BlockMutualInformation::gain(std::size_t first_row) const {
  const auto r = static_cast<Eigen::Index>(first_row);
  const long a = lambda_row_.at(first_row), b = lambda_row_.at(first_row + 1);
  if (a < 0 || b < 0) return 0.0;  // a deterministic block shares no information
  const double detP = P_.block<2, 2>(r, r).determinant();
  Eigen::Matrix2d L;
  L << lambda_(a, a), lambda_(a, b), lambda_(b, a), lambda_(b, b);
  return 0.5 * std::log2(detP * L.determinant());
}

void BlockMutualInformation::removeBlock(std::size_t first_row) {
  const auto r = static_cast<Eigen::Index>(first_row);
  const long a = lambda_row_.at(first_row), b = lambda_row_.at(first_row + 1);
  if (a >= 0 && b >= 0) {
    if (b != a + 1) throw std::logic_error("block rows are not contiguous in Lambda");
    // Schur complement of Lambda_LL: the information of the remaining variables.
    const Eigen::Matrix2d LLinv = lambda_.block<2, 2>(a, a).inverse();
    const Eigen::MatrixXd cross = lambda_.middleCols(a, 2);
    lambda_.noalias() -= cross * LLinv * cross.transpose();
    eraseRowsCols(lambda_, a, 2);
  }
  eraseRowsCols(P_, r, 2);
  lambda_row_.erase(lambda_row_.begin() + r, lambda_row_.begin() + r + 2);
  if (a >= 0 && b >= 0)
    for (auto& v : lambda_row_)
      if (v > b) v -= 2;
}

}  // namespace budget_slam::ekf
