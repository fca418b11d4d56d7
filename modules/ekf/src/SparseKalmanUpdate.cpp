#include "budget_slam/ekf/SparseKalmanUpdate.h"

#include <algorithm>
#include <stdexcept>

namespace budget_slam::ekf {

namespace {

/// H d for a state-sized vector d: two entries a reading.
Eigen::VectorXd applyH(const std::vector<ReadingJacobian>& H, const Eigen::VectorXd& d) {
  Eigen::VectorXd out(2 * static_cast<Eigen::Index>(H.size()));
  for (std::size_t k = 0; k < H.size(); ++k)
    out.segment<2>(2 * static_cast<Eigen::Index>(k)) =
        H[k].robot * d.head<3>() + H[k].landmark * d.segment<2>(H[k].landmark_row);
  return out;
}

}  // namespace

void sparseKalmanUpdate(Eigen::Ref<RowMajorMatrix> P, Eigen::Ref<Eigen::VectorXd> x,
                        const std::vector<ReadingJacobian>& H, const Eigen::MatrixXd& S_inverse,
                        const Eigen::VectorXd& innovation, int iterations) {
  const Eigen::Index n = P.rows(), m2 = 2 * static_cast<Eigen::Index>(H.size());
  if (P.cols() != n || x.size() != n || S_inverse.rows() != m2 || S_inverse.cols() != m2 ||
      innovation.size() != m2 || iterations < 1)
    throw std::invalid_argument("sparseKalmanUpdate: sizes do not agree");
  if (H.empty()) return;
  for (const auto& h : H)
    if (h.landmark_row < 3 || h.landmark_row + 2 > n)
      throw std::invalid_argument("sparseKalmanUpdate: a landmark outside the state");

  // W = H P from P's robot rows and each observed landmark's rows (rows of a row-major P are
  // contiguous); P Hᵀ = Wᵀ for a symmetric P.
  RowMajorMatrix W(m2, n);
  for (std::size_t k = 0; k < H.size(); ++k)
    W.middleRows<2>(2 * static_cast<Eigen::Index>(k)).noalias() =
        H[k].robot * P.topRows<3>() + H[k].landmark * P.middleRows<2>(H[k].landmark_row);
  const Eigen::MatrixXd K = W.transpose() * S_inverse;  // n x 2m

  if (iterations == 1) {
    x.noalias() += K * innovation;
  } else {
    const Eigen::VectorXd x0 = x;
    for (int it = 0; it < iterations; ++it) {
      const Eigen::VectorXd moved = applyH(H, x - x0);
      x = x0;
      x.noalias() += K * (innovation - moved);
    }
  }

  // P - K W is symmetric: each B x B block of the lower triangle is computed once and written to
  // its mirror block while it is still in cache (one pass over P; a separate mirroring pass
  // would read the lower triangle again, column-wise).
  constexpr Eigen::Index B = 64;
  for (Eigen::Index i0 = 0; i0 < n; i0 += B) {
    const Eigen::Index bi = std::min(B, n - i0);
    const auto Ki = K.middleRows(i0, bi);
    for (Eigen::Index j0 = 0; j0 < i0; j0 += B) {
      auto block = P.block(i0, j0, bi, B);
      block.noalias() -= Ki * W.middleCols(j0, B);
      P.block(j0, i0, B, bi) = block.transpose();
    }
    // The diagonal block whole (its upper half costs B² m flops a block), then its lower half
    // mirrored.
    P.block(i0, i0, bi, bi).noalias() -= Ki * W.middleCols(i0, bi);
    for (Eigen::Index i = i0; i < i0 + bi; ++i)
      for (Eigen::Index j = i0; j < i; ++j) P(j, i) = P(i, j);
  }
}

}  // namespace budget_slam::ekf
