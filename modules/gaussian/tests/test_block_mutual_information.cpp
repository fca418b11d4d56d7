#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <random>

#include "budget_slam/gaussian/BlockMutualInformation.h"

using budget_slam::gaussian::BlockMutualInformation;

namespace {

Eigen::MatrixXd randomSpd(int n, std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = g(rng);
  return A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

/// Independent brute force: 1/2 log2(det(P_LL) det((P^-1)_LL)) with a full LU inverse.
double bruteForce(const Eigen::MatrixXd& P, int r) {
  const Eigen::MatrixXd Lambda = P.fullPivLu().inverse();
  return 0.5 *
         std::log2(P.block(r, r, 2, 2).determinant() * Lambda.block(r, r, 2, 2).determinant());
}

Eigen::MatrixXd erase(const Eigen::MatrixXd& P, int r) {
  std::vector<int> keep;
  for (int i = 0; i < P.rows(); ++i)
    if (i != r && i != r + 1) keep.push_back(i);
  Eigen::MatrixXd out(keep.size(), keep.size());
  for (size_t i = 0; i < keep.size(); ++i)
    for (size_t j = 0; j < keep.size(); ++j) out(i, j) = P(keep[i], keep[j]);
  return out;
}

}  // namespace

TEST(BlockMutualInformation, EqualsBruteForceOnRandomSpdMatrices) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int landmarks = 3 + trial;
    const Eigen::MatrixXd P = randomSpd(3 + 2 * landmarks, rng);
    BlockMutualInformation mi(P);
    for (int l = 0; l < landmarks; ++l) {
      const double expected = bruteForce(P, 3 + 2 * l);
      EXPECT_NEAR(mi.gain(3 + 2 * l), expected, 1e-9 * std::max(1.0, std::abs(expected)));
      EXPECT_GE(mi.gain(3 + 2 * l), -1e-12);
    }
  }
}

TEST(BlockMutualInformation, SuccessiveRemovalsEqualAFreshComputation) {
  std::mt19937 rng(11);
  Eigen::MatrixXd P = randomSpd(3 + 2 * 30, rng);
  BlockMutualInformation mi(P);
  for (int k : {7, 0, 12, 3, 20, 1}) {
    const int r = 3 + 2 * k;
    mi.removeBlock(r);
    P = erase(P, r);
    BlockMutualInformation fresh(P);
    ASSERT_EQ(mi.size(), static_cast<std::size_t>(P.rows()));
    for (int l = 0; l < (P.rows() - 3) / 2; ++l)
      EXPECT_NEAR(mi.gain(3 + 2 * l), fresh.gain(3 + 2 * l), 1e-9) << "after removing " << k;
    // The Schur-updated information blocks are those of the reduced covariance's inverse.
    const Eigen::MatrixXd Lambda = P.inverse();
    for (int l = 0; l < (P.rows() - 3) / 2; ++l) {
      const int row = 3 + 2 * l;
      EXPECT_LT((mi.informationBlock(row) - Lambda.block(row, row, 2, 2)).cwiseAbs().maxCoeff(),
                1e-9 * Lambda.cwiseAbs().maxCoeff())
          << "after removing " << k;
    }
  }
}

TEST(BlockMutualInformation, DeterministicRobotPoseCarriesNoInformation) {
  // The EKF's first step: robot covariance exactly zero, landmarks independent of it.
  std::mt19937 rng(3);
  Eigen::MatrixXd L = randomSpd(8, rng);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(11, 11);
  P.bottomRightCorner(8, 8) = L;
  BlockMutualInformation mi(P);
  BlockMutualInformation reduced(L);
  for (int l = 0; l < 4; ++l) EXPECT_NEAR(mi.gain(3 + 2 * l), reduced.gain(2 * l), 1e-12);
  mi.removeBlock(3 + 2);
  BlockMutualInformation reduced2(erase(L, 2));
  for (int l = 0; l < 3; ++l) EXPECT_NEAR(mi.gain(3 + 2 * l), reduced2.gain(2 * l), 1e-9);
}

TEST(BlockMutualInformation, IndependentBlockHasZeroGain) {
  std::mt19937 rng(5);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(7, 7);
  P.topLeftCorner(5, 5) = randomSpd(5, rng);
  P.bottomRightCorner(2, 2) = randomSpd(2, rng);
  BlockMutualInformation mi(P);
  EXPECT_NEAR(mi.gain(5), 0.0, 1e-12);
  EXPECT_GT(mi.gain(3), 0.0);
}

TEST(BlockMutualInformation, LargeStatesAcrossKernelBlocks) {
  // Sizes that leave partial register tiles and panels (the kernels work in 8 x 4 tiles and
  // 32-wide panels): every landmark's gain and information block against a dense inverse.
  std::mt19937 rng(13);
  for (int landmarks : {14, 15, 16, 61, 120}) {
    const Eigen::MatrixXd P = randomSpd(3 + 2 * landmarks, rng);
    const Eigen::MatrixXd Lambda = P.fullPivLu().inverse();
    BlockMutualInformation mi(P);
    for (int l = 0; l < landmarks; ++l) {
      const int row = 3 + 2 * l;
      const double expected = bruteForce(P, row);
      EXPECT_NEAR(mi.gain(row), expected, 1e-9 * std::max(1.0, std::abs(expected))) << l;
      EXPECT_LT((mi.informationBlock(row) - Lambda.block(row, row, 2, 2)).cwiseAbs().maxCoeff(),
                1e-9 * Lambda.cwiseAbs().maxCoeff());
    }
  }
}

TEST(BlockMutualInformation, IndefiniteCovarianceIsAnError) {
  // Positive variances, but the landmark block [1 2; 2 1] has a negative eigenvalue.
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(7, 7);
  P(3, 4) = P(4, 3) = 2.0;
  EXPECT_THROW(BlockMutualInformation{P}, std::runtime_error);
}

TEST(BlockMutualInformation, AsymmetricRoundOffReadsTheSymmetricPart) {
  // A filter covariance whose triangles differ by round-off larger than its smallest eigenvalue:
  // its lower triangle alone is indefinite, its symmetric part is not. The gains are those of the
  // symmetric part.
  std::mt19937 rng(3);
  const Eigen::MatrixXd S = randomSpd(9, rng);
  Eigen::MatrixXd P = S;
  // v = (e3 + e4) / sqrt(2) gives v^T lower v = (S33 + S44 + 2 S34) / 2 - shift < 0.
  const double shift = 0.2 + 0.5 * (S(3, 3) + S(4, 4) + 2 * S(3, 4));
  for (int i = 1; i < 9; ++i)
    for (int j = 0; j < i; ++j) {
      P(i, j) += i == 4 && j == 3 ? -shift : 0.0;
      P(j, i) += i == 4 && j == 3 ? shift : 0.0;
    }
  Eigen::MatrixXd lower = P.triangularView<Eigen::Lower>();
  lower.triangularView<Eigen::StrictlyUpper>() =
      P.triangularView<Eigen::StrictlyLower>().transpose();
  ASSERT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(lower).eigenvalues()(0), 0.0);
  const BlockMutualInformation mi(P);
  for (int r = 3; r < 9; r += 2) EXPECT_NEAR(mi.gain(r), bruteForce(S, r), 1e-9) << "row " << r;
}
