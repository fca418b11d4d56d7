#include <gtest/gtest.h>

#include <cmath>

#include "budget_slam/metrics/MapAlignment.h"

using namespace budget_slam;
using namespace budget_slam::metrics;

namespace {
/// The true frame seen from a map turned by 30 deg and shifted by (2, -1).
const MapAlignment kTruth = MapAlignment::fromPose(2, -1, M_PI / 6, "test", 0);
}  // namespace

TEST(MapAlignment, FromLandmarksRecoversTheTransform) {
  dataset::GroundTruth gt;
  std::vector<LandmarkView> map;
  for (int i = 0; i < 5; ++i) {
    gt.landmarks[i] = Eigen::Vector2d(i * 1.5, (i % 2) * 3.0);
    LandmarkView l;
    l.id = i;
    l.mean = kTruth.transform.apply(gt.landmarks[i]);
    map.push_back(l);
  }
  const auto a = mapAlignment(map, {}, gt, 0);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->source, "landmarks");
  EXPECT_EQ(a->points, 5u);
  EXPECT_NEAR(a->yaw(), M_PI / 6, 1e-12);
  const auto p = a->apply({1, 1, 0.5});
  const auto q = kTruth.apply({1, 1, 0.5});
  EXPECT_NEAR(p.x, q.x, 1e-12);
  EXPECT_NEAR(p.y, q.y, 1e-12);
  EXPECT_NEAR(p.phi, 0.5 + M_PI / 6, 1e-12);
}

TEST(MapAlignment, FallsBackToTrajectoryThenStartPose) {
  dataset::GroundTruth gt;
  gt.path = {{3, 4, M_PI / 2}, {3, 5, M_PI / 2}, {2, 5, M_PI}};
  std::vector<TrajectoryPoint> traj;
  for (StepIndex k = 0; k < 2; ++k) {
    const auto t = kTruth.apply(gt.path[k + 1]);
    traj.push_back({k, double(k + 1), t});
  }
  const auto a = mapAlignment({}, traj, gt, 2);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->source, "trajectory");
  EXPECT_NEAR(a->yaw(), M_PI / 6, 1e-12);

  // No estimate to fit: the start pose becomes the origin.
  const auto b = mapAlignment({}, {}, gt, 2);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->source, "start_pose");
  const auto o = b->apply(gt.path[0]);
  EXPECT_NEAR(o.x, 0, 1e-12);
  EXPECT_NEAR(o.y, 0, 1e-12);
  EXPECT_NEAR(o.phi, 0, 1e-12);

  EXPECT_FALSE(mapAlignment({}, {}, dataset::GroundTruth(), 0));
}
