#pragma once
#include <Eigen/Core>
#include <stdexcept>
#include <vector>

namespace budget_slam::gaussian {

/// Mutual information between one 2-D block L of a Gaussian state and all the rest, in bits:
///   I(L; rest) = 1/2 log2( |P_LL| * |Lambda_LL| ),  Lambda = P^-1
/// (Choudhary et al. Eq. 6 with |Sigma_L|rest| = |Lambda_LL|^-1; docs/ALGORITHMS.md "mi", EKF
/// case).
///
/// Only the 2x2 diagonal blocks of Lambda are needed. With P = L L^T (Cholesky) and W = L^-1,
/// Lambda = W^T W, so Lambda_LL is the Gram matrix of W's two columns of L: one Cholesky and one
/// triangular inverse, n^3/3 multiply-adds in all (forming Lambda would take three times that).
///
/// Removing blocks marginalizes them: the information of the rest is the Schur complement
///   Lambda' = Lambda_rr - Lambda_rS Lambda_SS^-1 Lambda_Sr   (S: every block removed so far),
/// kept exactly as Lambda - V V^T on the remaining rows, V gaining two columns per removal:
/// with c = the current information's columns of the removed block (Lambda's columns W^T W_{:,L}
/// minus V V_L^T, O(n^2)) and G G^T = c_L, the new columns are c G^-T. A gain then costs
/// O(n + removals). No new factorization within one drop event.
///
/// State components with zero variance (the robot pose before its first motion) are
/// deterministic: they carry no information and are left out of Lambda.
class BlockMutualInformation {
 public:
  /// Thrown by the constructor when P is not positive definite (beyond round-off): I(L; rest)
  /// is then undefined.
  struct NotPositiveDefinite : std::runtime_error {
    NotPositiveDefinite() : std::runtime_error("covariance is not positive definite") {}
  };

  explicit BlockMutualInformation(const Eigen::MatrixXd& P);

  /// I(block starting at row `first_row`; rest) [bits]. The block has 2 rows.
  double gain(std::size_t first_row) const;

  /// Marginalizes the block out of P and Lambda (rows of P above it shift down by 2).
  void removeBlock(std::size_t first_row);

  std::size_t size() const { return lambda_row_.size(); }
  /// The current information block Lambda_LL of the 2 rows at `first_row` (both deterministic:
  /// zero), for tests.
  Eigen::Matrix2d informationBlock(std::size_t first_row) const;

 private:
  /// Lambda(a, b) for a <= b, indices into the active components.
  double lambda(long a, long b) const;

  long m_ = 0;                    ///< active (non-deterministic) components
  std::vector<double> w_;         ///< W = L^-1, m x m column-major, lower triangular
  std::vector<long> lambda_row_;  ///< row of the current P -> active index, -1 if deterministic
  std::vector<double> p_diag_;    ///< P(i, i) of the current rows
  std::vector<double> p_next_;    ///< P(i, i + 1) of the current rows (0 on the last)
  Eigen::MatrixXd V_;             ///< m x 2k: current information = Lambda - V V^T
};

}  // namespace budget_slam::gaussian
