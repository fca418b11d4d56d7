// Incremental solving: the kept ordering (IncrementalOrdering) against a fresh analysis at every
// factorization, the relinearization threshold, and the bounded graph (max_poses).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "TestGraphs.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/graph/InformationGain.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
RangeBearingNoise noiseOf() { return testgraphs::sensorNoise(0.05, 0.01 * 180 / M_PI); }

/// Largest difference between the two graphs' estimates (same structure), yaw wrapped.
double maxDiff(const FactorGraph& a, const FactorGraph& b) {
  Eigen::VectorXd d = a.values() - b.values();
  for (const auto& [s, p] : a.poses()) d[p.col + 2] = wrapAngle(d[p.col + 2]);
  return d.size() ? d.lpNorm<Eigen::Infinity>() : 0.0;
}

double maxDiffTo(const FactorGraph& g, const Eigen::VectorXd& ref) {
  Eigen::VectorXd d = g.values() - ref;
  for (const auto& [s, p] : g.poses()) d[p.col + 2] = wrapAngle(d[p.col + 2]);
  return d.lpNorm<Eigen::Infinity>();
}

GraphSlamOptions withFill(double fill) {
  GraphSlamOptions o;
  o.reorder_fill_ratio = fill;
  return o;
}

/// Runs `steps` through a backend keeping its ordering and one analysing afresh at every
/// structure change, in lockstep: after every incremental update (every relinearization) both
/// estimates and the latest pose's marginal must agree; every 50 steps the information gains from
/// the kept-ordering query factor must equal the fresh one's. Returns the number of updates.
std::size_t expectKeptEqualsFresh(const std::vector<Step>& steps, const RangeBearingNoise& noise,
                                  double tol) {
  GraphBackend kept(withFill(1.5), noise), fresh(withFill(0), noise);
  std::size_t compared = 0;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const std::size_t before = kept.updateCount();
    kept.process(steps[k]);
    fresh.process(steps[k]);
    EXPECT_EQ(kept.updateCount(), fresh.updateCount()) << "step " << k;
    if (kept.updateCount() != before) {
      ++compared;
      EXPECT_LT(maxDiff(kept.graph(), fresh.graph()), tol) << "step " << k;
      EXPECT_LT((kept.robotPose().cov - fresh.robotPose().cov).cwiseAbs().maxCoeff(), tol)
          << "step " << k;
    }
    if (k % 50 == 49 && kept.landmarkCount() > 0) {
      std::vector<LandmarkId> ids;
      for (const auto& [id, l] : kept.graph().landmarks()) ids.push_back(id);
      const std::vector<double> a = kept.informationGain(ids), b = fresh.informationGain(ids);
      for (std::size_t j = 0; j < ids.size(); ++j)
        EXPECT_NEAR(a[j], b[j], 1e-9 * std::max(1.0, std::abs(b[j]))) << "landmark " << ids[j];
    }
  }
  kept.finish();
  fresh.finish();
  EXPECT_LT(maxDiff(kept.graph(), fresh.graph()), 1e-9);
  // Both ways were taken: kept orderings and fresh ones when the fill grew.
  EXPECT_GT(kept.solverOrdering().reusedAnalyses(), 0u);
  EXPECT_GT(kept.solverOrdering().freshAnalyses(), 0u);
  return compared;
}
}  // namespace

TEST(IncrementalGraph, KeptOrderingEqualsFreshAnalysisOnALoopClosingRun) {
  // Three laps of a 40-step loop: every lap re-sights the first lap's landmarks.
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(120, 24, 11);
  EXPECT_GT(expectKeptEqualsFresh(run.steps, noiseOf(), 1e-9), 10u);
}

TEST(IncrementalGraph, KeptOrderingEqualsFreshAnalysisOnVictoriaParkPrefix) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = testgraphs::victoriaParkSteps(1000, &noise);
  if (steps.empty()) GTEST_SKIP() << "rawlogs/victoria_park.rawlog not found";
  // Real data: 2 mm odometry next to 0.6 m range sigmas; the two orderings round differently.
  EXPECT_GT(expectKeptEqualsFresh(steps, noise, 1e-7), 50u);
}

TEST(IncrementalGraph, KeptOrderingIsReusedOnAChain) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = testgraphs::victoriaParkSteps(1000, &noise);
  if (steps.empty()) GTEST_SKIP() << "rawlogs/victoria_park.rawlog not found";
  GraphBackend b(withFill(1.5), noise);
  for (const Step& s : steps) b.process(s);
  // Most structure changes keep the ordering: fresh analyses are the rare case.
  EXPECT_GT(b.solverOrdering().reusedAnalyses(), 4 * b.solverOrdering().freshAnalyses());
}

TEST(IncrementalGraph, GainFromKeptOrderingEqualsNaiveReference) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(90, 20, 5);
  GraphBackend b(withFill(1.5), noiseOf());
  std::vector<LandmarkId> ids;
  for (const Step& s : run.steps) {
    b.process(s);
    ids.clear();
    for (const auto& [id, l] : b.graph().landmarks()) ids.push_back(id);
    if (!ids.empty()) b.informationGain(ids);  // a query at every step: the query ordering grows
  }
  const std::vector<double> fast = b.informationGain(ids);
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const double naive = naiveInformationGain(b.graph(), ids[j]);
    EXPECT_NEAR(fast[j], naive, 1e-9 * std::max(1.0, std::abs(naive))) << "landmark " << ids[j];
  }
}

TEST(IncrementalGraph, RelinearizeThresholdSkipsIterationsThatWouldNotMove) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(100, 20, 7);
  GraphSlamOptions huge, one, zero;
  huge.relinearize_threshold = 1e9;  // every update stops after its first step
  one.incremental_iterations = 1;
  zero.relinearize_threshold = 0;
  GraphBackend a(huge, noiseOf()), b(one, noiseOf()), c(zero, noiseOf()),
      d(GraphSlamOptions{}, noiseOf());
  bool differs = false;
  for (const Step& s : run.steps) {
    a.process(s);
    b.process(s);
    c.process(s);
    d.process(s);
    EXPECT_EQ(maxDiff(a.graph(), b.graph()), 0.0);
    EXPECT_EQ(maxDiff(c.graph(), d.graph()), 0.0);
    differs |= maxDiff(a.graph(), c.graph()) > 1e-12;
  }
  EXPECT_TRUE(differs);  // the second iterations did move something
  a.finish();
  EXPECT_LT(maxDiffTo(a.graph(), testgraphs::denseBatchSolve(a.graph())), 1e-9);
}

TEST(IncrementalGraph, BoundedGraphKeepsPosesUnderTheLimitAndMemoryFlat) {
  // Ten laps of the loop with at most 60 poses: the oldest leave every few steps.
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(400, 24, 13);
  GraphSlamOptions o;
  o.max_poses = 60;
  GraphBackend b(o, noiseOf());
  std::set<LandmarkId> seen;
  std::size_t min_factors = ~std::size_t(0), max_factors = 0;
  for (std::size_t k = 0; k < run.steps.size(); ++k) {
    b.process(run.steps[k]);
    ASSERT_LE(b.poseCount(), 60u) << "step " << k;
    for (const RangeBearingReading& z : run.steps[k].scan->readings) seen.insert(z.id);
    EXPECT_EQ(b.landmarkCount(), seen.size()) << "step " << k;  // no landmark is lost
    if (k >= 100) {  // the window is full: its size stays flat
      min_factors = std::min(min_factors, b.graph().factorCount());
      max_factors = std::max(max_factors, b.graph().factorCount());
    }
  }
  EXPECT_GT(b.posesDropped(), 300u);
  EXPECT_EQ(b.trajectory().front().step, b.posesDropped());
  EXPECT_LE(static_cast<double>(max_factors), 1.25 * static_cast<double>(min_factors));
  // Some landmarks carry a prior now; the gains still equal the naive reference on this graph.
  std::vector<LandmarkId> ids;
  std::size_t priors = 0;
  for (const auto& [id, l] : b.graph().landmarks()) {
    ids.push_back(id);
    priors += l.prior.has_value();
  }
  const std::vector<double> fast = b.informationGain(ids);
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const double naive = naiveInformationGain(b.graph(), ids[j]);
    EXPECT_NEAR(fast[j], naive, 1e-9 * std::max(1.0, std::abs(naive))) << "landmark " << ids[j];
  }
  // The window still tracks the truth: finish() reaches the optimum of the bounded graph.
  b.finish();
  EXPECT_LT(maxDiffTo(b.graph(), testgraphs::denseBatchSolve(b.graph())), 1e-9);
  for (const TrajectoryPoint& p : b.trajectory())
    EXPECT_LT(std::hypot(p.pose.x - run.truth[p.step].x(), p.pose.y - run.truth[p.step].y()), 0.5)
        << "step " << p.step;
  for (const LandmarkView& v : b.landmarks())
    EXPECT_LT((v.mean - run.landmarks[v.id]).norm(), 0.75) << v.id;  // unbounded: 0.3
  (void)priors;
}

TEST(IncrementalGraph, LandmarkPriorKeepsAnOrphanedLandmarkWhereItWas) {
  // A landmark seen only by poses that leave keeps its estimate and marginal as a prior.
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(30, 24, 17, true, 6.0);
  GraphSlamOptions o;
  o.max_poses = 10;
  GraphBackend b(o, noiseOf());
  std::size_t with_prior = 0;
  for (const Step& s : run.steps) {
    b.process(s);
    for (const auto& [id, l] : b.graph().landmarks()) with_prior += l.prior.has_value();
  }
  EXPECT_GT(with_prior, 0u);
  for (const auto& [id, l] : b.graph().landmarks())
    if (l.prior && l.obs.empty()) EXPECT_LT((l.x - l.prior->mean).norm(), 1e-12) << id;
}
