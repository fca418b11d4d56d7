// Waking up on hand-made maps: found where the robot is, with ids and without; refused with too
// few landmarks or a degenerate geometry; a mirror-symmetric layout without ids is ambiguous,
// never a wrong pose.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <sstream>

#include "WakeUpTestUtil.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/wakeup/GlobalLocalizer.h"

using namespace budget_slam;
using namespace budget_slam::wakeup;
using namespace budget_slam::wakeup::test;

namespace {

/// A 20 m x 12 m room with landmarks placed without any symmetry.
const std::vector<WorldLandmark>& room() {
  static const std::vector<WorldLandmark> w = {
      {10, {0.5, 0.8}},  {11, {3.2, -0.4}}, {12, {6.1, 1.7}},  {13, {9.4, 0.2}},
      {14, {13.0, 2.9}}, {15, {17.8, 1.1}}, {16, {19.2, 6.3}}, {17, {15.5, 10.4}},
      {18, {11.1, 8.8}}, {19, {7.3, 11.5}}, {20, {2.6, 9.9}},  {21, {-0.3, 5.2}},
      {22, {5.0, 5.6}},  {23, {9.9, 4.4}},  {24, {14.2, 6.8}}, {25, {12.4, 12.2}}};
  return w;
}

SensorSetup noisySensor(bool with_ids) {
  SensorSetup s;
  s.on_robot = Pose2(0.25, 0.0, 0.0);
  s.max_range = 8;
  s.fov = M_PI;  // 180 degrees ahead
  s.std_range = 0.05;
  s.std_bearing = 0.5 * M_PI / 180;
  s.with_ids = with_ids;
  return s;
}

const ReadingNoise kNoise{0.05, 0.5 * M_PI / 180};

/// The pose error of a result against the truth at the step it is of: (metres, degrees).
std::pair<double, double> errorOf(const WakeUpResult& r, const std::vector<Pose2>& path,
                                  StepIndex first = 0) {
  const Pose2& t = path[r.step - first];
  const Pose2 p = r.pose.mean;
  return {(p.translation() - t.translation()).norm(),
          std::abs(wrapAngle(p.phi - t.phi)) * 180 / M_PI};
}

}  // namespace

TEST(WakeUp, WithIdsFindsTheRobotFromItsFirstStep) {
  std::mt19937 rng(7);
  const auto path = straightPath(Pose2(4.0, 3.0, 0.6), 10, 0.4);
  const auto steps = stepsAlong(path, room(), noisySensor(true), rng, 0.01, 500);
  const auto r = wakeUp(mapOf(room()), steps, WakeUpOptions{}, kNoise);
  ASSERT_EQ(r.status, WakeUpStatus::Found) << reasonName(r.reason);
  EXPECT_TRUE(r.by_ids);
  EXPECT_EQ(r.steps_used, 1u);
  EXPECT_EQ(r.step, 500u);
  EXPECT_EQ(r.inliers, r.readings);
  EXPECT_GE(r.landmarks, 3u);
  const auto [dxy, dyaw] = errorOf(r, path, 500);
  EXPECT_LT(dxy, 0.1);
  EXPECT_LT(dyaw, 1.0);
  // The covariance is a 1-sigma statement about that error.
  EXPECT_LT(std::sqrt(r.pose.cov(0, 0)), 0.1);
  EXPECT_GT(std::sqrt(r.pose.cov(0, 0)), 1e-4);
}

TEST(WakeUp, WithIdsGathersStepsUntilTwoLandmarksAreSeen) {
  // Landmarks 40 m apart on a long corridor: one in range at a time, the second after a few
  // steps; the odometry in between carries the first reading along.
  const std::vector<WorldLandmark> world = {{1, {0, 2}}, {2, {7, -2}}, {3, {40, 0}}};
  SensorSetup s = noisySensor(true);
  s.max_range = 4.5;
  s.fov = 2 * M_PI;
  std::mt19937 rng(2);
  const auto path = straightPath(Pose2(0, 0, 0), 12, 0.5);
  const auto steps = stepsAlong(path, world, s, rng, 0.005);
  GlobalLocalizer g(mapOf(world), WakeUpOptions{}, kNoise);
  EXPECT_EQ(g.add(steps[0]).status, WakeUpStatus::NotFound);
  EXPECT_EQ(g.result().reason, WakeUpReason::TooFewLandmarks);
  EXPECT_EQ(g.result().landmarks, 1u);
  std::size_t k = 1;
  while (!g.finished()) g.add(steps[k++]);
  const auto& r = g.result();
  ASSERT_EQ(r.status, WakeUpStatus::Found) << reasonName(r.reason);
  EXPECT_GT(r.steps_used, 3u);  // landmark 2 comes into range at x = 2.5 m
  EXPECT_EQ(r.landmarks, 2u);
  const auto [dxy, dyaw] = errorOf(r, path);
  EXPECT_LT(dxy, 0.25);
  EXPECT_LT(dyaw, 5.0);
}

TEST(WakeUp, WithOneLandmarkInViewItIsNotFound) {
  const std::vector<WorldLandmark> world = {{1, {3, 0}}, {2, {30, 0}}};
  std::mt19937 rng(2);
  const auto path = straightPath(Pose2(0, 0, 0), 15, 0.1);
  const auto r = wakeUp(mapOf(world), stepsAlong(path, world, noisySensor(true), rng),
                        WakeUpOptions{}, kNoise);
  EXPECT_EQ(r.status, WakeUpStatus::NotFound);
  EXPECT_EQ(r.reason, WakeUpReason::TooFewLandmarks);
  EXPECT_EQ(r.steps_used, 10u);  // [WakeUp] max_steps
  EXPECT_EQ(r.landmarks, 1u);
}

TEST(WakeUp, CoincidentLandmarksAreADegenerateGeometry) {
  // Two ids, one place: the rotation about that place is not observed.
  const std::vector<WorldLandmark> world = {{1, {3, 1}}, {2, {3, 1}}};
  SensorSetup s = noisySensor(true);
  s.std_range = s.std_bearing = 0;
  std::mt19937 rng(2);
  const auto r =
      wakeUp(mapOf(world), stepsAlong(straightPath(Pose2(0, 0, 0), 3, 0.0), world, s, rng),
             WakeUpOptions{}, kNoise);
  EXPECT_EQ(r.status, WakeUpStatus::NotFound);
  EXPECT_EQ(r.reason, WakeUpReason::Degenerate);
}

TEST(WakeUp, AMovedLandmarkIsLeftOutNotFollowed) {
  auto world = room();
  std::mt19937 rng(5);
  const auto path = straightPath(Pose2(4.0, 3.0, 0.6), 10, 0.4);
  const auto steps = stepsAlong(path, world, noisySensor(true), rng, 0.01);
  auto map = mapOf(world);
  for (auto& l : map)
    if (l.id == 22) l.mean += Eigen::Vector2d(2.0, -1.5);  // moved since the map was made
  const auto r = wakeUp(map, steps, WakeUpOptions{}, kNoise);
  ASSERT_EQ(r.status, WakeUpStatus::Found);
  EXPECT_EQ(r.inliers + 1, r.readings);  // landmark 22's one reading is out
  const auto [dxy, dyaw] = errorOf(r, path);
  EXPECT_LT(dxy, 0.1);
  EXPECT_LT(dyaw, 1.0);
}

TEST(WakeUp, WithoutIdsFindsTheRobotBySearch) {
  std::mt19937 rng(11);
  const auto path = straightPath(Pose2(4.0, 3.0, 0.6), 10, 0.4);
  const auto steps = stepsAlong(path, room(), noisySensor(false), rng, 0.01);
  const auto r = wakeUp(mapOf(room()), steps, WakeUpOptions{}, kNoise);
  ASSERT_EQ(r.status, WakeUpStatus::Found) << statusName(r.status) << " " << reasonName(r.reason);
  EXPECT_FALSE(r.by_ids);
  EXPECT_GE(r.landmarks, 4u);
  EXPECT_GT(r.hypotheses, 0u);
  EXPECT_LE(r.runner_up + 2, r.landmarks);
  const auto [dxy, dyaw] = errorOf(r, path);
  EXPECT_LT(dxy, 0.1);
  EXPECT_LT(dyaw, 1.0);
}

TEST(WakeUp, WithoutIdsFromManyStartsNeverAWrongPose) {
  // Every start on a grid over the room, eight headings: found ones must be right.
  std::mt19937 rng(13);
  std::size_t found = 0, tried = 0;
  for (double x = 1; x < 19; x += 3)
    for (double y = 1; y < 12; y += 3)
      for (int h = 0; h < 8; ++h) {
        const auto path = straightPath(Pose2(x, y, h * M_PI / 4), 10, 0.3);
        const auto r =
            wakeUp(mapOf(room()), stepsAlong(path, room(), noisySensor(false), rng, 0.01),
                   WakeUpOptions{}, kNoise);
        ++tried;
        if (r.status != WakeUpStatus::Found) continue;
        ++found;
        const auto [dxy, dyaw] = errorOf(r, path);
        EXPECT_LT(dxy, 0.25) << x << " " << y << " " << h;
        EXPECT_LT(dyaw, 5.0) << x << " " << y << " " << h;
      }
  // Most starts see enough of the room to be found (the rest face a wall with < 4 landmarks).
  EXPECT_GT(found, tried / 2);
}

TEST(WakeUp, AMirrorSymmetricLayoutWithoutIdsIsAmbiguousNeverAWrongPose) {
  // Symmetric about both axes (so about the centre too): the pose and its half-turn about the
  // centre give the same readings.
  std::vector<WorldLandmark> world;
  LandmarkId id = 1;
  for (const double x : {-6.0, -2.5, 2.5, 6.0})
    for (const double y : {-3.0, 3.0}) world.push_back({id++, {x, y}});
  world.push_back({id++, {-4.5, 0}});
  world.push_back({id++, {4.5, 0}});
  SensorSetup s = noisySensor(false);
  s.fov = 2 * M_PI;
  s.max_range = 20;
  for (const Pose2& start : {Pose2(1.0, 0.5, 0.3), Pose2(-3.0, 1.0, 2.0), Pose2(0.0, 0.0, 0.0)}) {
    std::mt19937 rng(3);
    const auto path = straightPath(start, 10, 0.3);
    const auto r =
        wakeUp(mapOf(world), stepsAlong(path, world, s, rng, 0.01), WakeUpOptions{}, kNoise);
    EXPECT_EQ(r.status, WakeUpStatus::Ambiguous)
        << statusName(r.status) << " " << reasonName(r.reason);
    EXPECT_EQ(r.steps_used, 10u);
    EXPECT_EQ(r.runner_up, r.landmarks);  // the twin agrees as well
  }
  // The same layout with ids is no puzzle.
  s.with_ids = true;
  std::mt19937 rng(3);
  const auto path = straightPath(Pose2(1.0, 0.5, 0.3), 10, 0.3);
  const auto r =
      wakeUp(mapOf(world), stepsAlong(path, world, s, rng, 0.01), WakeUpOptions{}, kNoise);
  ASSERT_EQ(r.status, WakeUpStatus::Found);
  EXPECT_LT(errorOf(r, path).first, 0.1);
  // Two more landmarks break the symmetry: the twin pose now agrees with fewer landmarks and
  // misses the two it predicts in view: found, at the right pose.
  s.with_ids = false;
  world.push_back({id++, {1.0, -2.0}});
  world.push_back({id++, {-4.0, 1.5}});
  std::mt19937 rng2(3);
  const auto r2 =
      wakeUp(mapOf(world), stepsAlong(path, world, s, rng2, 0.01), WakeUpOptions{}, kNoise);
  ASSERT_EQ(r2.status, WakeUpStatus::Found)
      << statusName(r2.status) << " " << reasonName(r2.reason);
  EXPECT_LT(errorOf(r2, path).first, 0.1);
}

TEST(WakeUp, APlaceThatIsNotOnTheMapIsNotFound) {
  // The robot is somewhere else: its readings come from another random layout.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0, 30);
  std::vector<WorldLandmark> map_world, other;
  for (LandmarkId i = 0; i < 60; ++i) map_world.push_back({i, {u(rng), u(rng)}});
  for (LandmarkId i = 0; i < 60; ++i) other.push_back({100 + i, {u(rng), u(rng)}});
  SensorSetup s = noisySensor(false);
  s.fov = 2 * M_PI;
  for (int trial = 0; trial < 6; ++trial) {
    const auto path = straightPath(Pose2(u(rng), u(rng), u(rng)), 10, 0.3);
    const auto r =
        wakeUp(mapOf(map_world), stepsAlong(path, other, s, rng, 0.01), WakeUpOptions{}, kNoise);
    EXPECT_NE(r.status, WakeUpStatus::Found)
        << trial << " " << r.landmarks << " vs " << r.runner_up;
  }
}

TEST(WakeUp, WithIdsAMapOfAnotherPlaceWithTheSameIdsIsNotFound) {
  // The room's ids at random places: dropping readings one at a time would end with two
  // landmarks that fit; a pose most of the named landmarks disagree with is not a pose.
  const auto path = straightPath(Pose2(4.0, 3.0, 0.6), 10, 0.4);
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u}) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 20);
    std::vector<WorldLandmark> other;
    for (const auto& l : room()) other.push_back({l.id, {u(rng), u(rng) * 0.6}});
    const auto r =
        wakeUp(mapOf(other), stepsAlong(path, room(), noisySensor(true), rng, 0.01), {}, kNoise);
    EXPECT_NE(r.status, WakeUpStatus::Found) << seed << ": " << r.landmarks << " landmarks";
  }
}

TEST(WakeUp, OptionsComeFromOneTable) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("WakeUp", "max_steps", "5");
  ini.write("WakeUp", "correspondence", "search");
  ini.write("WakeUp", "max_std_yaw_deg", "3");
  WakeUpOptions o;
  o.loadFromConfigFile(ini, "WakeUp");
  EXPECT_EQ(o.max_steps, 5u);
  EXPECT_EQ(o.correspondence, Correspondence::Search);
  EXPECT_EQ(o.max_std_yaw_deg, 3.0);
  EXPECT_EQ(o.gate_chi2, 9.21);  // absent: the default
  std::ostringstream dump;
  o.dumpToTextStream(dump);
  EXPECT_NE(dump.str().find("correspondence           = search  // auto | ids | search"),
            std::string::npos);
  EXPECT_EQ(WakeUpOptions::keys().size(), 18u);
  ini.write("WakeUp", "correspondence", "ids-first");
  try {
    o.loadFromConfigFile(ini, "WakeUp");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "[WakeUp] correspondence = 'ids-first': must be one of auto, ids, search");
  }
}
