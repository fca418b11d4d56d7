#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>

#include <cmath>
#include <csignal>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/metrics/ReferenceMetrics.h"

using namespace budget_slam;
using namespace budget_slam::metrics;

TEST(ReferenceMetrics, TrajectoryAndLandmarkErrorsOverMatchedPosesAndIds) {
  std::vector<TrajectoryPoint> ref = {{0, 0, {0, 0, 0}}, {1, 1, {1, 0, 0.1}}, {2, 2, {2, 0, 0.2}}};
  // The reduced run kept poses 0 and 2 only: errors 0.3 m / 0.4 m, headings 0.01 / 0.03 rad.
  std::vector<TrajectoryPoint> red = {{0, 0, {0.3, 0, 0.01}}, {2, 2, {2, 0.4, 0.2 - 0.03}}};
  LandmarkView a, b, c;
  a.id = 1, a.mean = {5, 5};
  b.id = 2, b.mean = {6, 6};
  c.id = 3, c.mean = {7, 7};
  LandmarkView a2 = a, c2 = c;
  a2.mean = {5, 5.5};
  c2.mean = {7, 7};
  const auto m = compareTrajectories(ref, red, {a, b, c}, {a2, c2});
  EXPECT_EQ(m.poses, 2u);
  EXPECT_NEAR(m.ate, std::sqrt((0.09 + 0.16) / 2), 1e-12);
  EXPECT_NEAR(m.are_deg, (0.01 + 0.03) / 2 * 180 / M_PI, 1e-9);
  EXPECT_EQ(m.landmarks, 2u);
  EXPECT_NEAR(m.ale, std::sqrt(0.25 / 2), 1e-12);
}

TEST(ReferenceMetrics, EkfAgainstItselfIsZeroAndReducedRunIsMeasured) {
  const std::string root = BUDGET_SLAM_SOURCE_DIR;
  mrpt::config::CConfigFile ini(root + "/tests/data/EKF-SLAM_test_2d.ini");
  ekf::EkfBackend ref(ini), same(ini), reduced(ini);
  const auto steps = dataset::readAllSteps(root + "/rawlogs/kf-slam_demo.rawlog");
  for (const auto& s : steps) {
    ref.process(s);
    same.process(s);
    reduced.process(s);
    // A crude reduction: keep the 25 most recently added landmarks.
    while (reduced.landmarkCount() > 25) reduced.removeLandmark(reduced.landmarks().front().id);
  }
  const auto zero = compareWithReference(ref, same, 10000);
  EXPECT_EQ(zero.poses, 249u);
  EXPECT_EQ(zero.ate, 0.0);
  EXPECT_EQ(zero.ale, 0.0);
  EXPECT_EQ(zero.ud_percent, 0.0);
  EXPECT_EQ(zero.eig_min, 0.0);
  EXPECT_EQ(zero.eig_rows, 3u + 2 * 70);

  const auto m = compareWithReference(ref, reduced, 10000);
  EXPECT_EQ(m.landmarks, 25u);
  EXPECT_GT(m.ate, 0.0);
  EXPECT_GT(m.ud_percent, 0.0);  // fewer landmarks: a less certain latest pose
  // UD as the growth of the pose's standard deviations: the sixth root of the determinants' ratio
  // (a 3x3 covariance), from the two covariances directly.
  const double ratio = reduced.robotPose().cov.determinant() / ref.robotPose().cov.determinant();
  EXPECT_NEAR(m.ud_std_factor, std::pow(ratio, 1.0 / 6), 1e-12);
  EXPECT_NEAR(std::pow(m.ud_std_factor, 6), 1 + m.ud_percent / 100,
              1e-9 * (1 + m.ud_percent / 100));
  EXPECT_EQ(zero.ud_std_factor, 1.0);
  EXPECT_EQ(m.eig_rows, 3u + 2 * 25);
  // Marginalizing landmarks out of the EKF never makes it more certain than the full filter:
  // Sigma_ref - Sigma_reduced has no clearly positive eigenvalue.
  EXPECT_LT(m.eig_min, 0.0);
  EXPECT_LE(m.eig_min, m.eig_max);

  const auto skipped = compareWithReference(ref, reduced, 10);
  EXPECT_TRUE(std::isnan(skipped.eig_min));
  EXPECT_EQ(skipped.eig_rows, 0u);

  // A stop request skips EIG (seconds on long graph runs) and nothing else.
  Cancellation::request(SIGTERM);
  const auto stopped = compareWithReference(ref, reduced, 10000);
  Cancellation::clear();
  EXPECT_TRUE(std::isnan(stopped.eig_min));
  EXPECT_TRUE(std::isnan(stopped.eig_max));
  EXPECT_EQ(stopped.eig_rows, 0u);
  EXPECT_EQ(stopped.ate, m.ate);
  EXPECT_EQ(stopped.ud_percent, m.ud_percent);
  EXPECT_EQ(stopped.landmarks, m.landmarks);
}
