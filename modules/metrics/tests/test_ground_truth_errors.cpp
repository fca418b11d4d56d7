#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/NeesAccumulator.h"

using namespace budget_slam;
using namespace budget_slam::metrics;

TEST(GroundTruthErrors, RowMappingFollowsSimulLandmarks) {
  EXPECT_EQ(groundTruthRow(0, 250, 249), 1u);  // start pose written first
  EXPECT_EQ(groundTruthRow(248, 250, 249), 249u);
  EXPECT_EQ(groundTruthRow(5, 100, 100), 5u);
  EXPECT_EQ(groundTruthRow(5, 250, 100), 6u);  // a run stopped after 100 steps
}

TEST(GroundTruthErrors, TrajectoryLandmarkAndNeesAgainstKnownErrors) {
  dataset::GroundTruth gt;
  // Start pose at (10, 5, 90 deg): the estimate's origin. Truth moves 1 m a step along its +x.
  const double yaw0 = M_PI / 2;
  gt.path.push_back({10, 5, yaw0});
  for (int k = 1; k <= 4; ++k) gt.path.push_back({10, 5.0 + k, yaw0});
  gt.landmarks[7] = Eigen::Vector2d(8, 7);  // 2 m ahead, 2 m to the left: estimate frame (2, 2)

  std::vector<TrajectoryPoint> traj;
  std::vector<PoseRecord> online;
  const double errs[4] = {0.0, 0.3, 0.4, 0.0};  // lateral errors, metres
  for (int k = 0; k < 4; ++k) {
    TrajectoryPoint p;
    p.step = k;
    p.pose = {k + 1.0, errs[k], 0.0};
    traj.push_back(p);
    PoseRecord r;
    r.step = k;
    r.estimate.mean = p.pose;
    r.estimate.cov = Eigen::Vector3d(0.01, 0.04, 0.01).asDiagonal();
    online.push_back(r);
  }
  LandmarkView l;
  l.id = 7;
  l.mean = Eigen::Vector2d(2.0, 2.5);
  LandmarkView unknown;
  unknown.id = 99;

  const auto e = groundTruthErrors(traj, {l, unknown}, gt, 4);
  EXPECT_EQ(e.poses, 4u);
  EXPECT_NEAR(e.trajectory_rmse, std::sqrt((0.09 + 0.16) / 4), 1e-12);
  EXPECT_NEAR(e.trajectory_max, 0.4, 1e-12);
  EXPECT_EQ(e.landmarks, 1u);
  EXPECT_NEAR(e.landmark_rmse, 0.5, 1e-12);
  // The NEES of the same run, accumulated online as a run does.
  NeesAccumulator nees(gt);
  for (const auto& r : online) nees.add(r.step, r.estimate);
  const NeesMean n = nees.result(4);
  EXPECT_EQ(n.samples, 4u);
  EXPECT_NEAR(n.mean, (0.09 / 0.04 + 0.16 / 0.04) / 4, 1e-12);
}

TEST(GroundTruthErrors, AlignmentRemovesARigidRotationOfTheWholeEstimate) {
  dataset::GroundTruth gt;
  gt.path.push_back({0, 0, 0});
  std::vector<TrajectoryPoint> traj;
  const double a = 0.7;  // the estimate is the truth rotated by 0.7 rad about (1, 1)
  const Eigen::Rotation2Dd R(a);
  for (int k = 0; k < 30; ++k) {
    const Eigen::Vector2d p(0.3 * k, std::sin(0.2 * k));
    gt.path.push_back({p.x(), p.y(), 0});
    const Eigen::Vector2d q = R * (p - Eigen::Vector2d(1, 1)) + Eigen::Vector2d(1, 1);
    TrajectoryPoint t;
    t.step = k;
    t.pose = {q.x(), q.y(), 0};
    traj.push_back(t);
  }
  gt.landmarks[3] = Eigen::Vector2d(2, 5);
  LandmarkView l;
  l.id = 3;
  l.mean = R * (Eigen::Vector2d(2, 5) - Eigen::Vector2d(1, 1)) + Eigen::Vector2d(1, 1) +
           Eigen::Vector2d(0.1, 0);
  const auto e = groundTruthErrors(traj, {l}, gt, 30);
  EXPECT_GT(e.trajectory_rmse, 0.5);
  EXPECT_NEAR(e.trajectory_rmse_aligned, 0.0, 1e-12);
  EXPECT_NEAR(e.alignment_rotation_deg, -a * 180 / M_PI, 1e-9);
  EXPECT_NEAR(e.landmark_rmse_aligned, 0.1, 1e-9);
}
