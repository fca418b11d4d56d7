// GraphBackend::clone(): a disposable deep copy for look-ahead (Choudhary et al. Alg. 3). It gives
// the same estimates, covariances and information gains as the original and evolves on its own.
#include <gtest/gtest.h>

#include "TestGraphs.h"
#include "budget_slam/graph/GraphBackend.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
RangeBearingNoise noiseOf() {
  RangeBearingNoise n;
  n.std_sensor_range = 0.05;
  n.std_sensor_yaw_deg = 0.5;
  return n;
}

std::vector<LandmarkId> idsOf(const Backend& b) {
  std::vector<LandmarkId> ids;
  for (const LandmarkView& v : b.landmarks()) ids.push_back(v.id);
  return ids;
}

/// Same poses, landmarks, covariances and gains, bit for bit.
void expectSame(const Backend& a, const Backend& b) {
  const auto ta = a.trajectory(), tb = b.trajectory();
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t k = 0; k < ta.size(); ++k) {
    EXPECT_EQ(ta[k].step, tb[k].step);
    EXPECT_EQ(ta[k].pose.x, tb[k].pose.x);
    EXPECT_EQ(ta[k].pose.y, tb[k].pose.y);
    EXPECT_EQ(ta[k].pose.phi, tb[k].pose.phi);
  }
  const auto la = a.landmarks(), lb = b.landmarks();
  ASSERT_EQ(la.size(), lb.size());
  for (std::size_t k = 0; k < la.size(); ++k) {
    EXPECT_EQ(la[k].id, lb[k].id);
    EXPECT_EQ(la[k].mean, lb[k].mean);
    EXPECT_EQ(la[k].cov, lb[k].cov);
    EXPECT_EQ(la[k].n_obs, lb[k].n_obs);
    EXPECT_EQ(la[k].obs_mean, lb[k].obs_mean);
    EXPECT_EQ(la[k].last_step, lb[k].last_step);
  }
  EXPECT_EQ(a.robotPose().cov, b.robotPose().cov);
  const auto ids = idsOf(a);
  EXPECT_EQ(a.informationGain(ids), b.informationGain(ids));
}
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
  expectSame(b, *copy);
  // A copy taken after queries (the original holds a factorization; the copy rebuilds its own).
  std::unique_ptr<Backend> twin = b.clone();
  expectSame(b, *twin);

  // The copy loses landmarks and poses; the original does not notice.
  const auto ids = idsOf(*copy);
  const std::vector<double> gains_before = b.informationGain(ids);
  std::size_t removed = 0;
  for (const LandmarkView& v : copy->landmarks())
    if (v.last_step < 40) copy->removeLandmark(v.id), ++removed;
  ASSERT_GT(removed, 0u);
  EXPECT_GT(copy->marginalizePosesWithoutLandmarks(5), 0u);
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
  expectSame(b, *twin);
  b.finish();
  twin->finish();
  expectSame(b, *twin);
}
