#include "budget_slam/gaussian/BlockMutualInformation.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

#include "DenseInverseKernels.h"

namespace budget_slam::gaussian {

BlockMutualInformation::BlockMutualInformation(const Eigen::MatrixXd& P) {
  const Eigen::Index n = P.rows();
  const double max_diag = n > 0 ? P.diagonal().maxCoeff() : 0.0;
  lambda_row_.assign(static_cast<std::size_t>(n), -1);
  p_diag_.resize(static_cast<std::size_t>(n));
  p_next_.assign(static_cast<std::size_t>(n), 0.0);
  std::vector<Eigen::Index> active;
  // The filter's covariance is symmetric only up to its update's round-off (MRPT's
  // P - K S K^T): on the lifelong run the two triangles differ by 1e-4 where the smallest
  // eigenvalue is 2e-5, so either triangle alone can be indefinite. The gains are those of the
  // symmetric part (P + P^T) / 2, which is what the filter means.
  for (Eigen::Index i = 0; i < n; ++i) {
    p_diag_[i] = P(i, i);
    if (i + 1 < n) p_next_[i] = 0.5 * (P(i, i + 1) + P(i + 1, i));
    if (P(i, i) > 1e-15 * max_diag) {
      lambda_row_[static_cast<std::size_t>(i)] = static_cast<long>(active.size());
      active.push_back(i);
    }
  }
  m_ = static_cast<long>(active.size());
  const std::size_t m = static_cast<std::size_t>(m_);
  w_.resize(m * m);
  const auto load = [&](double jitter) {
    for (std::size_t c = 0; c < m; ++c)
      for (std::size_t r = c; r < m; ++r)
        w_[r + c * m] = 0.5 * (P(active[r], active[c]) + P(active[c], active[r]));
    for (std::size_t c = 0; c < m; ++c) w_[c + c * m] += jitter;
  };
  load(0.0);
  if (!detail::choleskyLowerInPlace(w_.data(), m, m)) {
    // Round-off can leave an EKF covariance a hair from positive definite; a relative jitter far
    // below any physical variance restores the factorization.
    double mean = 0;
    for (Eigen::Index i : active) mean += P(i, i);
    load(1e-12 * mean / static_cast<double>(std::max<std::size_t>(1, m)));
    if (!detail::choleskyLowerInPlace(w_.data(), m, m)) throw NotPositiveDefinite();
  }
  std::vector<double> scratch(64 * std::max<std::size_t>(1, m));
  detail::invertLowerInPlace(w_.data(), m, m, scratch.data());
  V_.resize(m_, 0);
}

double BlockMutualInformation::lambda(long a, long b) const {
  // (W^T W)(a, b) = sum over rows k >= b of W(k, a) W(k, b) (W lower triangular, a <= b).
  const double* wa = w_.data() + a * m_;
  const double* wb = w_.data() + b * m_;
  double s = 0;
  for (long k = b; k < m_; ++k) s += wa[k] * wb[k];
  return s;
}

Eigen::Matrix2d BlockMutualInformation::informationBlock(std::size_t first_row) const {
  const long a = lambda_row_.at(first_row), b = lambda_row_.at(first_row + 1);
  Eigen::Matrix2d L = Eigen::Matrix2d::Zero();
  if (a < 0 && b < 0) return L;
  // V V^T (i, j). Before the first removal V has no column: Eigen would form its row as an offset
  // from a null data pointer (undefined behaviour, UBSan's finding), so that product is 0 here.
  const auto vv = [&](long i, long j) { return V_.cols() == 0 ? 0.0 : V_.row(i).dot(V_.row(j)); };
  if (a < 0 || b < 0) {  // one deterministic component: only the other's information
    const long c = a < 0 ? b : a;
    const double v = lambda(c, c) - vv(c, c);
    (a < 0 ? L(1, 1) : L(0, 0)) = v;
    return L;
  }
  L(0, 0) = lambda(a, a) - vv(a, a);
  L(1, 1) = lambda(b, b) - vv(b, b);
  L(0, 1) = L(1, 0) = lambda(std::min(a, b), std::max(a, b)) - vv(a, b);
  return L;
}

double BlockMutualInformation::gain(std::size_t first_row) const {
  const long a = lambda_row_.at(first_row), b = lambda_row_.at(first_row + 1);
  if (a < 0 || b < 0) return 0.0;  // a deterministic block shares no information
  const double detP =
      p_diag_[first_row] * p_diag_[first_row + 1] - p_next_[first_row] * p_next_[first_row];
  return 0.5 * std::log2(detP * informationBlock(first_row).determinant());
}

void BlockMutualInformation::removeBlock(std::size_t first_row) {
  const long a = lambda_row_.at(first_row), b = lambda_row_.at(first_row + 1);
  if (a >= 0 && b >= 0) {
    if (b != a + 1) throw std::logic_error("block rows are not contiguous in Lambda");
    // c = the current information's two columns of the block: Lambda_{:,L} - V V_L^T, with
    // Lambda(i, a) = W(:, i) . W(:, a) over rows >= max(i, a).
    Eigen::MatrixXd c(m_, 2);
    for (long i = 0; i < m_; ++i) {
      c(i, 0) = i <= a ? lambda(i, a) : lambda(a, i);
      c(i, 1) = i <= b ? lambda(i, b) : lambda(b, i);
    }
    if (V_.cols() > 0) c.noalias() -= V_ * V_.middleRows(a, 2).transpose();
    // Schur complement of the block: current information -= c c_L^-1 c^T = v v^T, v = c G^-T.
    const Eigen::Matrix2d cL = c.middleRows(a, 2);
    const Eigen::LLT<Eigen::Matrix2d> G(cL);
    if (G.info() != Eigen::Success)
      throw std::runtime_error("information block is not positive definite");
    const Eigen::MatrixXd v = G.matrixL().solve(c.transpose()).transpose();
    V_.conservativeResize(Eigen::NoChange, V_.cols() + 2);
    V_.rightCols<2>() = v;
    V_.middleRows(a, 2).setZero();  // the removed rows: no longer read
  }
  const auto r = static_cast<std::ptrdiff_t>(first_row);
  lambda_row_.erase(lambda_row_.begin() + r, lambda_row_.begin() + r + 2);
  p_diag_.erase(p_diag_.begin() + r, p_diag_.begin() + r + 2);
  p_next_.erase(p_next_.begin() + r, p_next_.begin() + r + 2);
  // P(i, i+1) of the row just before the block now pairs it with the row just after: not a
  // diagonal block of any landmark (blocks start at 3 + 2k), so it is never read; zero it.
  if (r > 0) p_next_[static_cast<std::size_t>(r - 1)] = 0.0;
}

}  // namespace budget_slam::gaussian
