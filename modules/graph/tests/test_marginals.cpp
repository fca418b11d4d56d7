// Marginal and joint marginal covariances from the factor against a dense inverse.
#include <gtest/gtest.h>

#include "TestGraphs.h"
#include "budget_slam/graph/Marginals.h"
#include "budget_slam/graph/Solver.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
Eigen::MatrixXd denseBlock(const Eigen::MatrixXd& M, const std::vector<int>& idx) {
  Eigen::MatrixXd B(idx.size(), idx.size());
  for (std::size_t a = 0; a < idx.size(); ++a)
    for (std::size_t b = 0; b < idx.size(); ++b) B(a, b) = M(idx[a], idx[b]);
  return B;
}
}  // namespace

TEST(Marginals, JointMarginalEqualsDenseInverse) {
  SparseCholesky chol;
  FactorGraph g = testgraphs::solvedRandomGraph(50, 20, 3, &chol);
  const Eigen::MatrixXd Sigma = testgraphs::denseInformation(g).inverse();
  const std::vector<VariableKey> vars{VariableKey::pose(49), VariableKey::landmark(3),
                                      VariableKey::pose(0), VariableKey::pose(17),
                                      VariableKey::landmark(1000)};
  const Eigen::MatrixXd J = jointMarginal(g, chol, vars);
  const Eigen::MatrixXd ref = denseBlock(Sigma, columnsOf(g, vars));
  ASSERT_EQ(J.rows(), 13);
  EXPECT_LT((J - ref).norm(), 1e-9 * ref.norm());
}

TEST(Marginals, EachVariableMarginal) {
  SparseCholesky chol;
  FactorGraph g = testgraphs::solvedRandomGraph(40, 12, 9, &chol);
  const Eigen::MatrixXd Sigma = testgraphs::denseInformation(g).inverse();
  std::vector<VariableKey> vars;
  for (const auto& [id, l] : g.landmarks()) vars.push_back(VariableKey::landmark(id));
  for (const auto& [s, p] : g.poses()) vars.push_back(VariableKey::pose(s));
  const std::vector<Eigen::MatrixXd> m = marginals(g, chol, vars);
  ASSERT_EQ(m.size(), vars.size());
  for (std::size_t k = 0; k < vars.size(); ++k) {
    const Eigen::MatrixXd ref = denseBlock(Sigma, columnsOf(g, {vars[k]}));
    EXPECT_LT((m[k] - ref).norm(), 1e-9 * ref.norm()) << k;
  }
}

TEST(Marginals, LogDetAndQuadraticForm) {
  FactorGraph g = testgraphs::randomGraph(30, 10, 4);
  SparseCholesky chol;
  factorizeAtEstimate(g, &chol);
  const Eigen::MatrixXd H = testgraphs::denseInformation(g);
  const double ref_logdet =
      2.0 * Eigen::LLT<Eigen::MatrixXd>(H).matrixLLT().diagonal().array().log().sum();
  EXPECT_NEAR(chol.logDet(), ref_logdet, 1e-10 * std::abs(ref_logdet));
  const std::vector<int> S{5, 0, 40, 41, 3};
  const Eigen::MatrixXd W = Eigen::MatrixXd::Random(3, 5);
  const Eigen::MatrixXd ref = W * denseBlock(H.inverse(), S) * W.transpose();
  EXPECT_LT((chol.inverseQuadraticForm(S, W) - ref).norm(), 1e-9 * ref.norm());
}
