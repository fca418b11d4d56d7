// Moved landmarks: a kept landmark read away from its estimate, while the rest of the view agrees
// with the map, from three distinct places that agree on one new place, has moved; its readings
// are held meanwhile. A pose error (every reading off together), one place read again, a reading
// back inside the gate, readings that scatter, or too few other landmarks in view never split.
#include <gtest/gtest.h>

#include <cmath>

#include "FakeBackend.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/MovedLandmarks.h"
#include "budget_slam/session/SessionState.h"

using namespace budget_slam;
using namespace budget_slam::reducers;

namespace {

const std::vector<Eigen::Vector2d> kWorld = {{3, 0}, {0, 3}, {-3, 0}, {0, -3}, {3, 3}};

/// The map of kWorld (landmark i + 1 at kWorld[i], 2 cm 1-sigma), the robot believed at `pose`
/// with 1 cm and 0.1 degree; no joint covariance (the test runs on the marginals).
class Map : public budget_slam::testing::FakeBackend {
 public:
  explicit Map(std::size_t landmarks = kWorld.size()) : FakeBackend(views(landmarks)) {
    cov.diagonal() << 1e-4, 1e-4, std::pow(0.1 * M_PI / 180, 2);
  }
  PoseEstimate robotPose() const override { return {pose, cov}; }
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();

 private:
  static std::vector<LandmarkView> views(std::size_t n) {
    std::vector<LandmarkView> out;
    for (std::size_t i = 0; i < n; ++i) {
      LandmarkView v =
          budget_slam::testing::landmark(static_cast<LandmarkId>(i + 1), 4e-4, 4e-4, 0, 0);
      v.mean = kWorld[i];
      out.push_back(v);
    }
    return out;
  }
};

/// A 360-degree scan of step `index` from a robot truly at `robot` (x, y, yaw) of the landmarks at
/// `where` (id i + 1 at where[i]), exact readings, no odometry.
Step scanFrom(const Eigen::Vector3d& robot, const std::vector<Eigen::Vector2d>& where,
              StepIndex index) {
  Step s;
  s.index = index;
  RangeBearingScan scan;
  scan.min_range = 0.1;
  scan.max_range = 20;
  scan.fov_yaw = 2 * M_PI;
  for (std::size_t i = 0; i < where.size(); ++i) {
    const Eigen::Vector2d d = where[i] - robot.head<2>();
    RangeBearingReading r;
    r.id = static_cast<LandmarkId>(i + 1);
    r.range = d.norm();
    r.yaw = std::remainder(std::atan2(d.y(), d.x()) - robot.z(), 2 * M_PI);
    scan.readings.push_back(r);
  }
  s.scan = scan;
  return s;
}

/// kWorld with landmark 5 moved by `by`.
std::vector<Eigen::Vector2d> movedWorld(const Eigen::Vector2d& by) {
  auto w = kWorld;
  w[4] += by;
  return w;
}

/// Three robot positions 1.5 m apart.
const std::vector<Eigen::Vector3d> kPlaces = {{0, 0, 0}, {1.5, 0, 0.3}, {0, 1.5, -0.2}};

/// Screens one step from `robot` (where the map also believes it) of `world`.
MovedScreening screenAt(MovedLandmarks& moved, Map& map, const Eigen::Vector3d& robot,
                        const std::vector<Eigen::Vector2d>& world, StepIndex index) {
  map.pose = Pose2(robot);
  return moved.screen(map, scanFrom(robot, world, index), std::nullopt);
}

}  // namespace

TEST(MovedLandmarks, SplitsAfterThreeDistinctPlacesAndHoldsItsReadingsMeanwhile) {
  MovedLandmarks moved({});
  Map map;
  const auto world = movedWorld({1, 0});
  for (std::size_t k = 0; k < 2; ++k) {
    const MovedScreening s = screenAt(moved, map, kPlaces[k], world, k);
    EXPECT_EQ(s.held, std::set<LandmarkId>{5}) << "place " << k;
    EXPECT_TRUE(s.moved.empty());
    ASSERT_EQ(moved.suspects().at(5).size(), k + 1);
    // The evidence puts it at its new place.
    EXPECT_LT((moved.suspects().at(5).back().point - world[4]).norm(), 1e-9);
  }
  const MovedScreening s = screenAt(moved, map, kPlaces[2], world, 2);
  ASSERT_EQ(s.moved.size(), 1u);
  EXPECT_EQ(s.moved[0].first, 5);
  EXPECT_GT(s.moved[0].second, 13.8155);  // the mean NIS of its evidence
  EXPECT_TRUE(s.held.empty());            // this reading starts the new landmark
  EXPECT_TRUE(moved.suspects().empty());
}

TEST(MovedLandmarks, OnePlaceReadAgainCountsOnce) {
  MovedLandmarks moved({});
  Map map;
  const auto world = movedWorld({1, 0});
  for (StepIndex k = 0; k < 10; ++k) {
    const Eigen::Vector3d here(0.1 * static_cast<double>(k % 3), 0, 0);  // within 1 m
    const MovedScreening s = screenAt(moved, map, here, world, k);
    EXPECT_EQ(s.held, std::set<LandmarkId>{5});
    EXPECT_TRUE(s.moved.empty());
  }
  EXPECT_EQ(moved.suspects().at(5).size(), 1u);
}

TEST(MovedLandmarks, APoseErrorMovesEveryReadingAndIsNoEvidence) {
  MovedLandmarks moved({});
  Map map;
  for (StepIndex k = 0; k < 3; ++k) {
    // The robot is 0.5 m and 5 degrees from where the map believes it: every reading is off.
    map.pose = Pose2(kPlaces[k]);
    const Eigen::Vector3d truly = kPlaces[k] + Eigen::Vector3d(0.5, 0, 5 * M_PI / 180);
    const MovedScreening s = moved.screen(map, scanFrom(truly, kWorld, k), std::nullopt);
    EXPECT_TRUE(s.held.empty());
    EXPECT_TRUE(s.moved.empty());
  }
  EXPECT_TRUE(moved.suspects().empty());
}

TEST(MovedLandmarks, AReadingBackInsideTheGateClearsTheSuspicion) {
  MovedLandmarks moved({});
  Map map;
  screenAt(moved, map, kPlaces[0], movedWorld({1, 0}), 0);
  screenAt(moved, map, kPlaces[1], movedWorld({1, 0}), 1);
  ASSERT_EQ(moved.suspects().at(5).size(), 2u);
  const MovedScreening s = screenAt(moved, map, kPlaces[2], kWorld, 2);  // where the map has it
  EXPECT_TRUE(s.held.empty());
  EXPECT_TRUE(moved.suspects().empty());
  // The count starts again: two more places do not split it.
  screenAt(moved, map, kPlaces[0], movedWorld({1, 0}), 3);
  EXPECT_TRUE(screenAt(moved, map, kPlaces[1], movedWorld({1, 0}), 4).moved.empty());
}

TEST(MovedLandmarks, ReadingsThatScatterAreNotOneNewPlace) {
  MovedLandmarks moved({});
  Map map;
  const std::vector<Eigen::Vector2d> by = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 0}};
  for (StepIndex k = 0; k < by.size(); ++k) {
    const MovedScreening s = screenAt(moved, map, kPlaces[k % 3], movedWorld(by[k]), k);
    EXPECT_EQ(s.held, std::set<LandmarkId>{5}) << "step " << k;
    EXPECT_TRUE(s.moved.empty()) << "step " << k;
  }
}

TEST(MovedLandmarks, NeedsTwoOtherLandmarksThatAgree) {
  MovedLandmarks moved({});
  Map map;
  // Only landmarks 1 and 5 in view: one other landmark agrees, fewer than min_agreeing = 2.
  for (StepIndex k = 0; k < 3; ++k) {
    map.pose = Pose2(kPlaces[k]);
    Step step = scanFrom(kPlaces[k], movedWorld({1, 0}), k);
    auto& r = step.scan->readings;
    r.erase(r.begin() + 1, r.begin() + 4);
    const MovedScreening s = moved.screen(map, step, std::nullopt);
    EXPECT_TRUE(s.held.empty());  // not a suspect yet: fused as MRPT would
    EXPECT_TRUE(s.moved.empty());
  }
  EXPECT_TRUE(moved.suspects().empty());
}

TEST(MovedLandmarks, TheBudgetRemovesItBeforeTheStepAndLogsItMoved) {
  BudgetOptions options;
  options.reducer = "none";
  options.max_landmarks.reset();
  options.moved_landmarks = BudgetOptions::MovedMode::Split;
  BudgetManager manager(options, nullptr);
  Map map;
  const auto world = movedWorld({1, 0});
  for (StepIndex k = 0; k < 2; ++k) {
    map.pose = Pose2(kPlaces[k]);
    const Step fused = manager.admit(map, scanFrom(kPlaces[k], world, k));
    ASSERT_EQ(fused.scan->readings.size(), 4u);  // landmark 5's reading held
    for (const auto& r : fused.scan->readings) EXPECT_NE(r.id, 5);
    EXPECT_TRUE(manager.enforce(map, fused).empty());
  }
  // The state goes with a session and comes back: the third place splits it there.
  session::SessionState state;
  manager.saveSession(state);
  ASSERT_NE(state.takeIfPresent("moved_landmarks"), nullptr);
  BudgetManager resumed(options, nullptr);
  resumed.restoreSession(state);
  ASSERT_EQ(resumed.movedLandmarks()->suspects().at(5).size(), 2u);
  map.pose = Pose2(kPlaces[2]);
  const Step fused = resumed.admit(map, scanFrom(kPlaces[2], world, 2));
  EXPECT_FALSE(map.has(5));                    // removed before the step is fused
  EXPECT_EQ(fused.scan->readings.size(), 5u);  // its reading starts the new landmark
  const std::vector<Eviction> drops = resumed.enforce(map, fused);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_EQ(drops[0].id, 5);
  EXPECT_EQ(drops[0].reason, "moved");
  EXPECT_EQ(drops[0].step, 2u);
  EXPECT_EQ(drops[0].n_before, 5u);
  EXPECT_EQ(drops[0].n_after, 4u);
  EXPECT_LT((drops[0].mean - kWorld[4]).norm(), 1e-12);
  EXPECT_TRUE(resumed.evicted().empty());  // the same sensor ID is the new landmark
}

TEST(MovedLandmarks, OffFusesEveryReading) {
  BudgetOptions options;
  options.reducer = "none";
  options.max_landmarks.reset();
  BudgetManager manager(options, nullptr);
  Map map;
  for (StepIndex k = 0; k < 3; ++k) {
    map.pose = Pose2(kPlaces[k]);
    EXPECT_EQ(manager.admit(map, scanFrom(kPlaces[k], movedWorld({1, 0}), k)).scan->readings.size(),
              5u);
  }
  EXPECT_EQ(manager.movedLandmarks(), nullptr);
}
