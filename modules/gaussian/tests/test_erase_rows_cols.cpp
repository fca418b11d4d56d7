// The one row/column erasure the EKF filter and the Gaussian evaluators share: the block of the
// dropped variable goes, everything else keeps its value and relative order, whatever the storage
// order (MRPT's matrices are row-major, Eigen's default column-major).
#include <gtest/gtest.h>

#include "budget_slam/gaussian/EraseRowsCols.h"

using namespace budget_slam::gaussian;

namespace {
Eigen::MatrixXd numbered(Eigen::Index n) {
  Eigen::MatrixXd M(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) M(i, j) = 10.0 * static_cast<double>(i) + j;
  return M;
}
}  // namespace

TEST(EraseRowsCols, DropsTheBlockAndKeepsTheRestInOrder) {
  Eigen::MatrixXd M = numbered(7);
  eraseRowsCols(M, 3, 2);
  const std::vector<Eigen::Index> kept = {0, 1, 2, 5, 6};
  ASSERT_EQ(M.rows(), 5);
  ASSERT_EQ(M.cols(), 5);
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (std::size_t j = 0; j < kept.size(); ++j)
      EXPECT_EQ(M(i, j), 10.0 * kept[i] + kept[j]) << i << "," << j;
}

TEST(EraseRowsCols, FirstAndLastBlocks) {
  Eigen::MatrixXd first = numbered(5), last = numbered(5);
  eraseRowsCols(first, 0, 2);
  eraseRowsCols(last, 3, 2);
  EXPECT_EQ(first, numbered(5).bottomRightCorner(3, 3));
  EXPECT_EQ(last, numbered(5).topLeftCorner(3, 3));
}

TEST(EraseRowsCols, RowMajorMapsAndVectors) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor M = numbered(6);
  RowMajor out(4, 4);
  copyWithoutRowsCols(M, 1, 2, Eigen::Map<RowMajor>(out.data(), 4, 4));
  Eigen::MatrixXd expected = numbered(6);
  eraseRowsCols(expected, 1, 2);
  EXPECT_EQ(Eigen::MatrixXd(out), expected);

  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(6, 0.0, 5.0);
  Eigen::VectorXd w(4);
  copyWithoutEntries(v, 1, 2, w);
  EXPECT_EQ(w, (Eigen::VectorXd(4) << 0.0, 3.0, 4.0, 5.0).finished());
}
