// The sparse solvers reach the batch optimum: a dense Gauss-Newton run to convergence.
#include <gtest/gtest.h>

#include <csignal>
#include <string>

#include "TestGraphs.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/graph/Solver.h"

using namespace budget_slam::graph;

namespace {
double maxStateDiff(const FactorGraph& g, const Eigen::VectorXd& ref) {
  Eigen::VectorXd d = g.values() - ref;
  for (const auto& [s, p] : g.poses()) d[p.col + 2] = wrapAngle(d[p.col + 2]);
  return d.lpNorm<Eigen::Infinity>();
}
}  // namespace

TEST(Solver, GaussNewtonReachesDenseBatchOptimum) {
  for (unsigned seed : {1u, 2u, 3u}) {
    FactorGraph g = testgraphs::randomGraph(40, 15, seed);
    const Eigen::VectorXd ref = testgraphs::denseBatchSolve(g);
    SparseCholesky chol;
    const SolveReport r = optimize(g, SolverSettings{}, &chol);
    EXPECT_TRUE(r.converged);
    EXPECT_LT(r.final_chi2, r.initial_chi2);
    EXPECT_LT(maxStateDiff(g, ref), 1e-9) << "seed " << seed;
  }
}

TEST(Solver, LevenbergMarquardtReachesDenseBatchOptimum) {
  FactorGraph g = testgraphs::randomGraph(40, 15, 7);
  const Eigen::VectorXd ref = testgraphs::denseBatchSolve(g);
  SolverSettings s;
  s.method = SolverSettings::Method::LevenbergMarquardt;
  s.max_iterations = 200;
  SparseCholesky chol;
  optimize(g, s, &chol);
  EXPECT_LT(maxStateDiff(g, ref), 1e-9);
}

TEST(Solver, GradientVanishesAtOptimum) {
  FactorGraph g = testgraphs::randomGraph(60, 20, 11);
  SparseCholesky chol;
  optimize(g, SolverSettings{}, &chol);
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd grad;
  g.linearize(&H, &grad);
  EXPECT_LT(grad.lpNorm<Eigen::Infinity>(), 1e-7);
}

TEST(Solver, WarmStartAfterStructureChange) {
  // Adding variables after a solve (new analysis) still converges to the new optimum.
  FactorGraph g = testgraphs::randomGraph(30, 10, 5);
  SparseCholesky chol;
  optimize(g, SolverSettings{}, &chol);
  g.removeLandmark(g.landmarks().begin()->first);
  const Eigen::VectorXd ref = testgraphs::denseBatchSolve(g);
  optimize(g, SolverSettings{}, &chol);
  EXPECT_LT(maxStateDiff(g, ref), 1e-9);
}

TEST(Solver, UnconstrainedLandmarkIsAnError) {
  FactorGraph g = testgraphs::randomGraph(10, 3, 5);
  g.addLandmark(77, Eigen::Vector2d(1, 1));  // no factor touches it: H is singular
  SparseCholesky chol;
  EXPECT_THROW(optimize(g, SolverSettings{}, &chol), std::runtime_error);
}

TEST(Solver, AStopRequestEndsAFullSolveBetweenIterations) {
  // Ctrl-C during the end phase's full solve: Interrupted before the next iteration, the estimate
  // left at the last accepted iterate; without stop_on_request (incremental solves) it runs on.
  FactorGraph g = testgraphs::randomGraph(40, 15, 4);
  const Eigen::VectorXd start = g.values();
  SolverSettings s;
  s.stop_on_request = true;
  SparseCholesky chol;
  budget_slam::Cancellation::request(SIGINT);
  try {
    optimize(g, s, &chol);
    ADD_FAILURE() << "no Interrupted";
  } catch (const budget_slam::Interrupted& e) {
    EXPECT_EQ(std::string(e.what()), "interrupted by Ctrl-C");
  }
  EXPECT_EQ(g.values(), start);
  s.stop_on_request = false;
  EXPECT_TRUE(optimize(g, s, &chol).converged);
  budget_slam::Cancellation::clear();
}
