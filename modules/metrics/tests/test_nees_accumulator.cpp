#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "budget_slam/metrics/LocalizationScore.h"
#include "budget_slam/metrics/NeesAccumulator.h"

using namespace budget_slam;
using namespace budget_slam::metrics;

namespace {

PoseEstimate poseAt(double x, double y, double yaw, double var) {
  PoseEstimate p;
  p.mean = {x, y, yaw};
  p.cov = Eigen::Matrix3d::Identity() * var;
  return p;
}

}  // namespace

TEST(NeesAccumulator, PoseNeesWrapsYawAndRejectsSingularCovariance) {
  PoseEstimate est = poseAt(0, 0, M_PI - 0.1, 0.01);
  EXPECT_NEAR(poseNees(est, {0, 0, -M_PI + 0.1}), 0.04 / 0.01, 1e-9);
  est.cov.setZero();
  EXPECT_TRUE(std::isnan(poseNees(est, {0, 0, 0})));
}

TEST(NeesAccumulator, PicksTheRowConventionOnceTheStepCountIsKnown) {
  // Path rows 0..3 at x = 0, 1, 2, 3. Steps 0..2 estimated at x = 1, 2, 3 (variance 1).
  dataset::GroundTruth gt;
  for (int k = 0; k < 4; ++k) gt.path.push_back({double(k), 0, 0});
  NeesAccumulator acc(gt);
  for (int k = 0; k < 3; ++k) acc.add(k, poseAt(k + 1.0, 0, 0, 1.0));
  // 3 steps, 4 rows: step k is row k+1 (the start pose first), every error is 0.
  const NeesMean shifted = acc.result(3);
  EXPECT_EQ(shifted.samples, 3u);
  EXPECT_NEAR(shifted.mean, 0.0, 1e-12);
  // 4 steps, 4 rows: step k is row k, every error is 1 m.
  const NeesMean same = acc.result(4);
  EXPECT_EQ(same.samples, 3u);
  EXPECT_NEAR(same.mean, 1.0, 1e-12);
}

TEST(NeesAccumulator, SkipsUndefinedStepsAndWorksInTheEstimateFrame) {
  // The truth starts at (10, 5) heading +y: the estimate's origin.
  dataset::GroundTruth gt;
  gt.path.push_back({10, 5, M_PI / 2});
  gt.path.push_back({10, 7, M_PI / 2});  // 2 m ahead
  NeesAccumulator acc(gt);
  acc.add(0, poseAt(2.0, 0.5, 0, 0.25));  // 0.5 m lateral error: NEES 0.25 / 0.25
  acc.add(1, poseAt(0, 0, 0, 0.0));       // singular covariance: skipped
  acc.add(5, poseAt(0, 0, 0, 1.0));       // no row for it: skipped
  const NeesMean n = acc.result(7);
  EXPECT_EQ(n.samples, 1u);
  EXPECT_NEAR(n.mean, 1.0, 1e-12);
}

TEST(NeesAccumulator, NoPathNoSample) {
  NeesAccumulator acc(dataset::GroundTruth{});
  acc.add(0, poseAt(0, 0, 0, 1.0));
  const NeesMean n = acc.result(1);
  EXPECT_EQ(n.samples, 0u);
  EXPECT_TRUE(std::isnan(n.mean));
}

TEST(NeesMeanSum, LeavesUndefinedValuesOutOfTheMean) {
  NeesMeanSum sum;
  EXPECT_EQ(sum.result().samples, 0u);
  EXPECT_TRUE(std::isnan(sum.result().mean));
  EXPECT_TRUE(sum.add(2.0));
  EXPECT_FALSE(sum.add(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(sum.add(std::numeric_limits<double>::infinity()));
  EXPECT_TRUE(sum.add(5.0));
  EXPECT_EQ(sum.result().samples, 2u);
  EXPECT_DOUBLE_EQ(sum.result().mean, 3.5);
}

TEST(NeesMeanSum, LocalizationScorerReportsTheSameMean) {
  // The traversal score and the run's accumulator share one sum: same inputs, same numbers.
  LocalizationScorer scorer(1.0, 2);
  NeesMeanSum sum;
  for (const double nees : {1.5, std::numeric_limits<double>::quiet_NaN(), 4.0, 0.5}) {
    scorer.add(0.1, 3, nees);
    sum.add(nees);
  }
  EXPECT_EQ(scorer.score().nees_samples, sum.result().samples);
  EXPECT_EQ(scorer.score().nees_mean, sum.result().mean);
  EXPECT_DOUBLE_EQ(scorer.score().nees_mean, 2.0);
}
