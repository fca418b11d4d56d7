#pragma once
#include <Eigen/Dense>

#include <vector>

namespace budget_slam::ekf {

/// The covariance as MRPT stores it (CMatrixDynamic is row-major).
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The two rows (range, bearing) one reading adds to the observation Jacobian H of a
/// range-bearing EKF-SLAM state (robot x, y, yaw, then 2 entries a landmark): zero everywhere but
/// in the robot's 3 columns and the observed landmark's 2.
struct ReadingJacobian {
  Eigen::Matrix<double, 2, 3> robot;  ///< d(range, bearing) / d(robot x, y, yaw)
  Eigen::Matrix2d landmark;           ///< d(range, bearing) / d(landmark x, y)
  Eigen::Index landmark_row = 0;      ///< the landmark's first entry in the state (3 + 2 i)
};

/// The EKF update of one joint reading of m landmarks that uses H's sparsity, for a state of n
/// entries:
///
///   W = H P           (2m x n: two rows of P a reading, O(n m))
///   K = Wᵀ S⁻¹        (the gain P Hᵀ S⁻¹ of a symmetric P, O(n m²))
///   x <- x + K ν
///   P <- P - K W      (= P - K S Kᵀ: the lower triangle, each block mirrored, O(n² m))
///
/// `S_inverse` is the inverse of the readings' innovation covariance S = H P Hᵀ + R (2m x 2m),
/// `innovation` ν = z - h(x) stacked in reading order. With iterations > 1 the mean is iterated
/// as MRPT's kfIKFFull does with H held fixed: x <- x0 + K (ν - H (x - x0)); the covariance is
/// updated once. The same update as MRPT's dense P <- (I - K H) P up to round-off; P is left
/// exactly symmetric. P must be symmetric on entry (only its rows are read).
void sparseKalmanUpdate(Eigen::Ref<RowMajorMatrix> P, Eigen::Ref<Eigen::VectorXd> x,
                        const std::vector<ReadingJacobian>& H, const Eigen::MatrixXd& S_inverse,
                        const Eigen::VectorXd& innovation, int iterations = 1);

}  // namespace budget_slam::ekf
