// GraphBackend::clone(): a disposable deep copy for look-ahead (Choudhary et al. Alg. 3). It gives
// the same estimates, covariances and information gains as the original and evolves on its own.
#include <gtest/gtest.h>

#include "BackendExpectations.h"

#include "TestGraphs.h"
#include "budget_slam/graph/GraphBackend.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
RangeBearingNoise noiseOf() { return testgraphs::sensorNoise(0.05, 0.5); }

}  // namespace

TEST(GraphClone, GivesTheSameAnswersAndEvolvesIndependently) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(90, 18, 11);
  GraphBackend b(GraphSlamOptions{}, noiseOf());
  for (int k = 0; k < 53; ++k) b.process(run.steps[k]);  // between two incremental updates
  const std::size_t n_landmarks = b.landmarkCount(), n_poses = b.poseCount();
  ASSERT_GT(n_landmarks, 5u);

  // A copy taken mid-run, before any query of the original (dead-reckoned pose covariance).
  std::unique_ptr<Backend> copy = b.clone();
  ASSERT_NE(copy, nullptr);
  EXPECT_EQ(copy->name(), "graph");
  budget_slam::testing::expectSameBackend(b, *copy);
  // A copy taken after queries (the original holds a factorization; the copy rebuilds its own).
  std::unique_ptr<Backend> twin = b.clone();
  budget_slam::testing::expectSameBackend(b, *twin);

  // The copy loses landmarks and poses; the original does not notice.
  const auto ids = budget_slam::testing::idsOf(*copy);
  const std::vector<double> gains_before = b.informationGain(ids);
  std::size_t removed = 0;
  for (const LandmarkView& v : copy->landmarks())
    if (v.last_step < 40) copy->removeLandmark(v.id), ++removed;
  ASSERT_GT(removed, 0u);
  ASSERT_NE(poseHistory(copy.get()), nullptr);
  EXPECT_GT(poseHistory(copy.get())->marginalizePosesWithoutLandmarks(5), 0u);
  EXPECT_EQ(copy->landmarkCount(), n_landmarks - removed);
  EXPECT_LT(copy->poseCount(), n_poses);
  EXPECT_EQ(b.landmarkCount(), n_landmarks);
  EXPECT_EQ(b.poseCount(), n_poses);
  EXPECT_EQ(b.informationGain(ids), gains_before);

  // Original and twin fed the same steps stay identical, to the batch optimum.
  for (std::size_t k = 53; k < run.steps.size(); ++k) {
    b.process(run.steps[k]);
    twin->process(run.steps[k]);
  }
  budget_slam::testing::expectSameBackend(b, *twin);
  b.finish();
  poseHistory(twin.get())->finish();
  budget_slam::testing::expectSameBackend(b, *twin);
}
