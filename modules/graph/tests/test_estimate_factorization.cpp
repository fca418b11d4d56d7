// EstimateFactorization: the factor of H and the graph state it is of, in one object; and the
// graph backend's queries through it after a step that added sightings to a factorized graph.
#include <gtest/gtest.h>

#include "TestGraphs.h"
#include "budget_slam/graph/EstimateFactorization.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/graph/Marginals.h"
#include "budget_slam/graph/Solver.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
/// The joint marginal of `vars` from a fresh factorization of `g` at its estimate.
Eigen::MatrixXd freshMarginal(const FactorGraph& g, const std::vector<VariableKey>& vars) {
  SparseCholesky chol;
  factorizeAtEstimate(g, &chol);
  return jointMarginal(g, chol, vars);
}
}  // namespace

TEST(EstimateFactorization, KnowsTheGraphStateItIsOf) {
  SparseCholesky solved;
  FactorGraph g = testgraphs::solvedRandomGraph(30, 12, 5, &solved);
  const StepIndex last = g.poses().rbegin()->first;
  const LandmarkId l = g.landmarks().begin()->first;
  EstimateFactorization f;
  EXPECT_FALSE(f.isCurrent(g));
  const std::vector<VariableKey> vars{VariableKey::pose(last), VariableKey::landmark(l)};
  const Eigen::MatrixXd before = f.jointMarginal(g, vars);
  EXPECT_TRUE(f.isCurrent(g));
  // The same numbers as the free functions give (another ordering: equal up to rounding).
  EXPECT_TRUE(before.isApprox(freshMarginal(g, vars), 1e-12));
  // A copy of it goes with a copy of the graph, current for it at once, with the same numbers.
  FactorGraph g2 = g;
  EstimateFactorization copy(f);
  EXPECT_FALSE(copy.isCurrent(g2));  // not yet tied to the copy
  copy.adopt(g2);
  EXPECT_TRUE(copy.isCurrent(g2));
  EXPECT_EQ(copy.jointMarginal(g2, vars), before);

  // Any change of values makes it stale, and the next query folds the change in.
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(g.dim());
  dx[g.column(VariableKey::landmark(l))] = 0.5;
  g.retract(dx);
  EXPECT_FALSE(f.isCurrent(g));
  const Eigen::MatrixXd after = f.jointMarginal(g, vars);
  EXPECT_TRUE(after.isApprox(freshMarginal(g, vars), 1e-12));
  EXPECT_GT((after - before).norm(), 1e-12);
  EXPECT_EQ(copy.jointMarginal(g2, vars), before);  // the copy's graph did not move
  // So does a change of structure: a new sighting of landmark l from the last pose.
  const std::map<LandmarkId, Eigen::Matrix2d> lm = f.landmarkMarginals(g);
  g.addObservation(
      last, l,
      RangeBearingFactor::make(3.0, 0.2, Pose2(), Eigen::Vector2d(0.01, 1e-4).asDiagonal()));
  EXPECT_FALSE(f.isCurrent(g));
  const Eigen::Matrix2d seen = f.landmarkMarginal(g, l);
  EXPECT_TRUE(seen.isApprox(freshMarginal(g, {VariableKey::landmark(l)}), 1e-12));
  EXPECT_LT(seen.trace(), lm.at(l).trace());  // the new sighting is in it
  EXPECT_TRUE(f.landmarkMarginals(g).at(l).isApprox(seen, 1e-12));
}

TEST(EstimateFactorization, BackendQueriesAfterAssociationSeeTheNewSightings) {
  // Without landmark IDs every step factorizes the graph for the association gate and then adds
  // the step's sightings and landmarks. Every query after the step must be of the graph with them
  // (a factor of the graph before them left new landmarks outside it: "index out of range").
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(60, 12, 10, /*with_ids=*/false);
  GraphSlamOptions opt;
  opt.association_gate_chi2 = 25;
  GraphBackend b(opt, testgraphs::sensorNoise(0.05, 0.01 * 180 / M_PI));
  std::size_t checked = 0;
  for (const Step& s : run.steps) {
    b.process(s);
    const std::vector<LandmarkView> views = b.landmarks();
    ASSERT_EQ(views.size(), b.landmarkCount());
    for (const LandmarkView& v : views) {
      const Eigen::Matrix2d fresh = freshMarginal(b.graph(), {VariableKey::landmark(v.id)});
      ASSERT_TRUE(v.cov.isApprox(fresh, 1e-9)) << "step " << s.index << " landmark " << v.id;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300u);
  b.finish();
  const StepIndex last = run.steps.back().index;
  EXPECT_TRUE(
      b.robotPose().cov.isApprox(freshMarginal(b.graph(), {VariableKey::pose(last)}), 1e-9));
}
