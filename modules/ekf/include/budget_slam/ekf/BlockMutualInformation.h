#pragma once
#include <Eigen/Core>
#include <stdexcept>
#include <vector>

namespace budget_slam::ekf {

/// Mutual information between one 2-D block L of a Gaussian state and all the rest, in bits:
///   I(L; rest) = 1/2 log2( |P_LL| * |Lambda_LL| ),  Lambda = P^-1
/// (Choudhary et al. Eq. 6 with |Sigma_L|rest| = |Lambda_LL|^-1; DESIGN.md "mi", EKF case).
///
/// One Cholesky factorization serves every block; removing a block updates Lambda by the Schur
/// complement  Lambda' = Lambda_rr - Lambda_rL Lambda_LL^-1 Lambda_Lr  (O(n^2), no new inverse),
/// which is the information matrix of P with the block's rows and columns deleted.
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

  std::size_t size() const { return static_cast<std::size_t>(P_.rows()); }
  const Eigen::MatrixXd& information() const { return lambda_; }

 private:
  Eigen::MatrixXd P_;
  Eigen::MatrixXd lambda_;
  std::vector<long> lambda_row_;  ///< row of P -> row of lambda_, -1 if deterministic
};

}  // namespace budget_slam::ekf
