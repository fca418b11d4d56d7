// The variable layout of FactorGraph (dense arrays rebuilt per structure change) and the
// variable-wise AMD ordering of SparseCholesky: same numbers as the map walk and CHOLMOD's own
// ordering.
#include <gtest/gtest.h>

#include <algorithm>

#include "TestGraphs.h"
#include "budget_slam/graph/SparseCholesky.h"

using namespace budget_slam;
using namespace budget_slam::graph;

TEST(VariableLayout, LinearizationCostEqualsChi2) {
  FactorGraph g = testgraphs::randomGraph(80, 25, 11);
  g.setLandmarkPrior(3, LandmarkPrior::make(g.landmark(3).x + Eigen::Vector2d(0.2, -0.1),
                                            Eigen::Vector2d(0.3, 0.5).asDiagonal()));
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd grad;
  double c = -1;
  g.linearize(&H, &grad, &c);
  EXPECT_GT(c, 0);
  EXPECT_NEAR(c, g.chi2(), 1e-12 * c);
}

TEST(VariableLayout, StartsPartitionTheColumns) {
  FactorGraph g = testgraphs::randomGraph(20, 6, 3);
  const std::vector<int>& s = g.variableStarts();
  ASSERT_EQ(s.size(), g.poses().size() + g.landmarks().size() + 1);
  EXPECT_EQ(s.front(), 0);
  EXPECT_EQ(s.back(), g.dim());
  std::size_t k = 0;
  for (const auto& [step, p] : g.poses()) EXPECT_EQ(s[k++], g.column(VariableKey::pose(step)));
  for (const auto& [id, l] : g.landmarks()) EXPECT_EQ(s[k++], g.column(VariableKey::landmark(id)));
}

TEST(VariableLayout, CopiesAndStructureChangesKeepTheirOwnLayout) {
  FactorGraph g = testgraphs::randomGraph(40, 12, 5);
  const Eigen::VectorXd v = g.values();  // builds the original's layout
  FactorGraph c = g;                     // must not point into g's nodes
  const Eigen::VectorXd dx = Eigen::VectorXd::Constant(v.size(), 0.01);
  c.retract(dx);
  EXPECT_EQ((g.values() - v).norm(), 0.0);
  EXPECT_LT((c.values() - v - dx).lpNorm<Eigen::Infinity>(), 1e-12);
  g.retract(dx);
  EXPECT_EQ((testgraphs::denseInformation(g) - testgraphs::denseInformation(c)).norm(), 0.0);
  EXPECT_EQ(g.chi2(), c.chi2());

  // A pose between two others leaves (a hole in the steps) and a landmark goes: the layout
  // follows, and both graphs still agree after the same changes.
  for (FactorGraph* x : {&g, &c}) x->removeLandmark(x->landmarks().begin()->first);
  // Make pose 10 removable in both: drop every landmark it sees.
  std::vector<LandmarkId> seen;
  for (const auto& [id, l] : g.landmarks())
    for (const Observation& o : l.obs)
      if (o.pose == 10) seen.push_back(id);
  for (FactorGraph* x : {&g, &c}) {
    for (LandmarkId id : seen)
      if (x->hasLandmark(id)) x->removeLandmark(id);
    ASSERT_TRUE(x->canMarginalizePose(10));
    x->marginalizePose(10);
  }
  EXPECT_EQ(g.dim(), c.dim());
  EXPECT_EQ(g.dim(), static_cast<int>(3 * g.poses().size() + 2 * g.landmarks().size()));
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd grad;
  double cost = 0;
  g.linearize(&H, &grad, &cost);
  EXPECT_NEAR(cost, c.chi2(), 1e-12 * cost);
  EXPECT_EQ((testgraphs::denseInformation(g) - testgraphs::denseInformation(c)).norm(), 0.0);
}

TEST(VariableOrdering, SameFactorAsCholmodsOwnOrderingWithVariablesTogether) {
  FactorGraph g = testgraphs::randomGraph(120, 30, 21);
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd grad;
  g.linearize(&H, &grad);
  SparseCholesky own, by_variable;
  ASSERT_TRUE(own.factorize(H));
  ASSERT_TRUE(by_variable.factorize(H, 0, &g.variableStarts()));
  EXPECT_NEAR(by_variable.logDet(), own.logDet(), 1e-10 * std::abs(own.logDet()));
  const Eigen::VectorXd x0 = own.solve(grad), x1 = by_variable.solve(grad);
  EXPECT_LT((x1 - x0).lpNorm<Eigen::Infinity>(), 1e-9 * x0.lpNorm<Eigen::Infinity>());
  // Each variable's columns are eliminated one after the other, in column order.
  const std::vector<int>& s = g.variableStarts();
  std::vector<int> pos(static_cast<std::size_t>(H.rows()));
  for (int c = 0; c < H.rows(); ++c) pos[c] = by_variable.position(c);
  for (std::size_t v = 0; v + 1 < s.size(); ++v)
    for (int c = s[v] + 1; c < s[v + 1]; ++c) EXPECT_EQ(pos[c], pos[c - 1] + 1) << "column " << c;
  // No more fill than AMD on the scalar pattern, up to a few percent.
  EXPECT_LE(by_variable.analysedNonZeros(), 1.05 * own.analysedNonZeros());
}

TEST(VariableLayout, ChangesInPlaceEqualAFreshLayout) {
  // Poses appended, landmarks added and removed (first, middle and last in id order) while the
  // layout is current change it in place; a copy of the graph builds its layout afresh: both the
  // same.
  FactorGraph g = testgraphs::randomGraph(30, 10, 7);
  const auto expectFresh = [](const FactorGraph& a, const std::string& where) {
    const FactorGraph fresh = a;  // a copy starts with an empty layout
    EXPECT_EQ(a.dim(), fresh.dim()) << where;
    EXPECT_EQ(a.variableStarts(), fresh.variableStarts()) << where;
    EXPECT_EQ(a.variableIndices(), fresh.variableIndices()) << where;
    for (const auto& [s, p] : fresh.poses())
      EXPECT_EQ(a.column(VariableKey::pose(s)), fresh.column(VariableKey::pose(s))) << where;
    for (const auto& [id, l] : fresh.landmarks())
      EXPECT_EQ(a.column(VariableKey::landmark(id)), fresh.column(VariableKey::landmark(id)))
          << where;
    EXPECT_EQ((a.values() - fresh.values()).norm(), 0.0) << where;
    EXPECT_EQ((testgraphs::denseInformation(a) - testgraphs::denseInformation(fresh)).norm(), 0.0)
        << where;
  };
  expectFresh(g, "start");
  const BetweenFactor odo =
      BetweenFactor::make(Pose2(1, 0, 0.1), Eigen::Vector3d(1e-2, 1e-2, 1e-3).asDiagonal());
  const Eigen::Matrix2d rb_cov = Eigen::Vector2d(0.01, 1e-4).asDiagonal();
  LandmarkId next_id = g.landmarks().rbegin()->first + 1;
  for (StepIndex s = 30; s < 36; ++s) {
    g.addPose(s, s, compose(Pose2(g.pose(s - 1).x), Pose2(1, 0, 0.1)), odo);
    g.addLandmark(next_id, g.pose(s).x.head<2>() + Eigen::Vector2d(1, 1));
    g.addObservation(s, next_id, RangeBearingFactor::make(1.4, 0.7, Pose2(), rb_cov));
    g.addObservation(s - 1, next_id, RangeBearingFactor::make(2.0, 0.5, Pose2(), rb_cov));
    ++next_id;
    // Oldest, a middle one and the newest leave in turn, the layout current before each.
    const auto& lm = g.landmarks();
    const LandmarkId gone = s % 3 == 0   ? lm.begin()->first
                            : s % 3 == 1 ? std::next(lm.begin(), lm.size() / 2)->first
                                         : lm.rbegin()->first;
    g.dim();
    g.removeLandmark(gone);
    expectFresh(g, "step " + std::to_string(s));
    // ... and comes back under its id (first, middle or last place in id order).
    g.addLandmark(gone, g.pose(s).x.head<2>() + Eigen::Vector2d(-1, 2));
    g.addObservation(s, gone, RangeBearingFactor::make(2.2, 2.0, Pose2(), rb_cov));
    expectFresh(g, "step " + std::to_string(s) + ", back");
    g.removeLandmark(gone);
  }
}
