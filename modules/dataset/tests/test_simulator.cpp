#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/poses/CPoint2D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <map>
#include <set>

#include "TestUtil.h"
#include "budget_slam/core/MrptPose.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/dataset/Simulator.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;
using mrpt::poses::CPose2D;

namespace {

using Kind = SimulationOptions::ScenarioKind;
using Route = SimulationOptions::Route;

SimulationOptions of(Kind scenario) {
  SimulationOptions o;
  o.scenario = scenario;
  return o;
}

std::string name(Kind scenario) { return nameOf(SimulationOptions::scenarioNames(), scenario); }

SimulationOptions zeroNoise(Kind scenario) {
  SimulationOptions o = of(scenario);
  o.odo_std_xy = o.odo_std_yaw_deg = o.sensor_std_range = o.sensor_std_yaw_deg = 0;
  return o;
}

double pathLength(const std::vector<Pose2>& path) {
  double len = 0;
  for (std::size_t k = 1; k < path.size(); ++k)
    len += std::hypot(path[k].x - path[k - 1].x, path[k].y - path[k - 1].y);
  return len;
}

}  // namespace

TEST(Simulator, SameSeedSameBytesOtherSeedOtherWorld) {
  TempDir tmp;
  SimulationOptions o;
  o.scenario = Kind::PaperSynthetic;
  simulateToFiles(o, tmp.file("a.rawlog"));
  simulateToFiles(o, tmp.file("b.rawlog"));
  for (const std::string suffix :
       {".rawlog", "_ground_truth.txt", "_ground_truth_robot_path.txt", ".ini"})
    EXPECT_EQ(readFile(tmp.file("a" + suffix)), readFile(tmp.file("b" + suffix))) << suffix;
  o.seed = 2;
  simulateToFiles(o, tmp.file("c.rawlog"));
  EXPECT_NE(readFile(tmp.file("a_ground_truth.txt")), readFile(tmp.file("c_ground_truth.txt")));
}

TEST(Simulator, ZeroNoiseRoundTripMatchesGroundTruth) {
  // Written, read back with RawlogReader, turned into poses (odometry composed from the start
  // pose) and points (pose + sensor pose + reading): equal to the ground truth. Poses to 1e-9;
  // points to 1e-5 m, the precision of MRPT's float32 range and bearing.
  for (const Kind scenario : {Kind::Rooms, Kind::PaperSynthetic}) {
    TempDir tmp;
    const std::string rawlog = tmp.file("z.rawlog");
    const auto n = simulateToFiles(zeroNoise(scenario), rawlog);
    const auto steps = readAllSteps(rawlog);
    const auto gt = loadGroundTruth(rawlog);
    ASSERT_EQ(steps.size(), n);
    ASSERT_EQ(gt.path.size(), n + 1) << name(scenario);
    CPose2D pose(toTPose2D(gt.path[0]));
    std::size_t points = 0;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      ASSERT_TRUE(steps[k].odometry);
      pose = pose + CPose2D(toTPose2D(steps[k].odometry->mean));
      EXPECT_NEAR(pose.x(), gt.path[k + 1].x, 1e-9) << name(scenario) << " step " << k;
      EXPECT_NEAR(pose.y(), gt.path[k + 1].y, 1e-9) << name(scenario) << " step " << k;
      EXPECT_NEAR(mrpt::math::wrapToPi(pose.phi() - gt.path[k + 1].phi), 0, 1e-9);
      const auto& scan = *steps[k].scan;
      const CPose2D sensor = pose + CPose2D(mrpt::poses::CPose3D(scan.sensor_pose_on_robot));
      for (const auto& r : scan.readings) {
        const auto p =
            sensor + mrpt::poses::CPoint2D(r.range * std::cos(r.yaw), r.range * std::sin(r.yaw));
        const auto& truth = gt.landmarks.at(r.id);
        EXPECT_NEAR(p.x(), truth.x(), 1e-5) << name(scenario) << " landmark " << r.id;
        EXPECT_NEAR(p.y(), truth.y(), 1e-5) << name(scenario) << " landmark " << r.id;
        ++points;
      }
    }
    EXPECT_GT(points, 300u) << name(scenario);
  }
}

TEST(Simulator, ScenarioSizesFollowThePapers) {
  const auto paper = simulate(of(Kind::PaperSynthetic));
  std::size_t readings = 0;
  for (const auto& s : paper.steps) readings += s.scan->readings.size();
  EXPECT_EQ(paper.ground_truth.landmarks.size(), 23u);
  EXPECT_EQ(paper.steps.size(), 96u);
  EXPECT_NEAR(static_cast<double>(readings), 420, 50);

  const auto rooms = simulate(of(Kind::Rooms));
  EXPECT_GE(rooms.ground_truth.landmarks.size(), 150u);
  EXPECT_NEAR(pathLength(rooms.ground_truth.path), 115, 10);

  const auto park = simulate(of(Kind::Park));
  EXPECT_EQ(park.ground_truth.landmarks.size(), 150u);
  EXPECT_GT(pathLength(park.ground_truth.path), 1500);
}

TEST(Simulator, ReadingsRespectRangeFieldOfViewAndRooms) {
  const auto d = simulate(zeroNoise(Kind::Rooms));
  // Rooms of the scenario in its output frame (the robot starts at (2, 2) of the plan).
  struct Box {
    double x0, y0, x1, y1;
    bool has(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
  };
  const std::vector<Box> rooms = {{-2, -2, 8, 6}, {-2, 6, 24, 8.5}, {14, -2, 24, 6}};
  auto roomOf = [&](double x, double y) {
    for (std::size_t i = 0; i < rooms.size(); ++i)
      if (rooms[i].has(x, y)) return static_cast<int>(i);
    return -1;
  };
  std::size_t checked = 0;
  for (std::size_t k = 0; k < d.steps.size(); ++k) {
    const auto& scan = *d.steps[k].scan;
    const auto& pose = d.ground_truth.path[k + 1];
    for (const auto& r : scan.readings) {
      EXPECT_GE(r.range, scan.min_range);
      EXPECT_LE(r.range, scan.max_range + 1e-6);
      EXPECT_LE(std::abs(r.yaw), scan.fov_yaw / 2 + 1e-6);
      const auto& l = d.ground_truth.landmarks.at(r.id);
      EXPECT_EQ(roomOf(l.x(), l.y()), roomOf(pose.x, pose.y)) << "step " << k << " id " << r.id;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000u);
}

TEST(Simulator, NoIdsKeepsTheReadingsWithoutIds) {
  SimulationOptions o;
  o.scenario = Kind::PaperSynthetic;
  const auto with = simulate(o);
  o.with_ids = false;
  const auto without = simulate(o);
  ASSERT_EQ(with.steps.size(), without.steps.size());
  for (std::size_t k = 0; k < with.steps.size(); ++k) {
    ASSERT_EQ(with.steps[k].scan->readings.size(), without.steps[k].scan->readings.size());
    for (std::size_t i = 0; i < with.steps[k].scan->readings.size(); ++i) {
      EXPECT_EQ(without.steps[k].scan->readings[i].id, kNoLandmarkId);
      EXPECT_EQ(without.steps[k].scan->readings[i].range, with.steps[k].scan->readings[i].range);
    }
  }
}

TEST(Simulator, NoiseHasTheStatedSpread) {
  SimulationOptions o;
  o.scenario = Kind::Park;
  const auto noisy = simulate(o);
  const auto& path = noisy.ground_truth.path;
  double sx = 0, sth = 0;
  for (std::size_t k = 0; k < noisy.steps.size(); ++k) {
    const CPose2D truth = CPose2D(toTPose2D(path[k + 1])) - CPose2D(toTPose2D(path[k]));
    sx += std::pow(noisy.steps[k].odometry->mean.x - truth.x(), 2);
    sth += std::pow(mrpt::math::wrapToPi(noisy.steps[k].odometry->mean.phi - truth.phi()), 2);
  }
  const double n = static_cast<double>(noisy.steps.size());
  const double std_x = std::sqrt(sx / n), std_th = std::sqrt(sth / n);
  // Stated in the rawlog: park's 0.03 m and 0.1 deg per step; 1814 samples: within 10 %.
  EXPECT_NEAR(std_x, 0.03, 0.003);
  EXPECT_NEAR(std_th, 0.1 * M_PI / 180, 0.01 * M_PI / 180);
  EXPECT_NEAR(std::sqrt(noisy.steps[0].odometry->cov(0, 0)), 0.03, 1e-12);
}

TEST(Simulator, LifelongWorldChangesBetweenLaps) {
  SimulationOptions o;
  o.scenario = Kind::Lifelong;
  o.laps = 3;
  Simulator sim(o);
  std::set<LandmarkId> seen;
  std::size_t steps = 0;
  sim.run([&](const Step& s) {
    ++steps;
    for (const auto& r : s.scan->readings) seen.insert(r.id);
  });
  const auto& gt = sim.groundTruth();
  EXPECT_GT(gt.landmarks.size(), 2000u);  // thousands of landmarks, more after each change
  EXPECT_EQ(gt.path.size(), steps + 1);
  // The lap is the same route each time: the robot is back at the start after every lap.
  std::size_t returns = 0;
  for (std::size_t k = 1; k < gt.path.size(); ++k)
    returns += std::hypot(gt.path[k].x, gt.path[k].y) < 0.3;
  EXPECT_GE(returns, 3u);
  // New landmarks appear: ids above the initial 150 + 24 x 80 = 2,070 are seen.
  EXPECT_GT(*seen.rbegin(), 2070);
}

// --route revisit: the same world (landmarks, ids, frame) driven from another start through
// every room or region; odometry and readings still reproduce the ground truth without noise.
TEST(Simulator, RevisitRouteDrivesTheSameWorldElsewhere) {
  for (const Kind scenario : {Kind::Rooms, Kind::Park}) {
    SimulationOptions first = zeroNoise(scenario), again = zeroNoise(scenario);
    again.route = Route::Revisit;
    const auto a = simulate(first), b = simulate(again);
    EXPECT_EQ(a.ground_truth.landmarks, b.ground_truth.landmarks) << name(scenario);
    const auto& start = b.ground_truth.path.front();
    EXPECT_GT(std::hypot(start.x, start.y), 5.0) << name(scenario);  // not the first start
    EXPECT_GT(pathLength(b.ground_truth.path), scenario == Kind::Rooms ? 70.0 : 700.0);
    CPose2D pose(toTPose2D(start));
    for (std::size_t k = 0; k < b.steps.size(); ++k) {
      pose = pose + CPose2D(toTPose2D(b.steps[k].odometry->mean));
      ASSERT_NEAR(pose.x(), b.ground_truth.path[k + 1].x, 1e-9) << name(scenario) << " step " << k;
      for (const auto& r : b.steps[k].scan->readings)
        ASSERT_TRUE(a.ground_truth.landmarks.count(r.id));
    }
    // Every room (rooms) or every quarter of the park (park) is driven through and seen.
    std::set<int> places;
    std::set<LandmarkId> seen;
    for (const auto& p : b.ground_truth.path) {
      // In the frame of the first start: lab x < 8, hallway y > 6, C12 x > 14 (rooms); the
      // park's 200 x 250 m split in four around its centre (80, 105).
      if (scenario == Kind::Rooms)
        places.insert(p.y > 6.1 ? 1 : (p.x < 8 ? 0 : 2));
      else
        places.insert((p.x > 80 ? 1 : 0) + (p.y > 105 ? 2 : 0));
    }
    for (const auto& st : b.steps)
      for (const auto& r : st.scan->readings) seen.insert(r.id);
    EXPECT_EQ(places.size(), scenario == Kind::Rooms ? 3u : 4u) << name(scenario);
    EXPECT_GT(seen.size(), a.ground_truth.landmarks.size() / 2) << name(scenario);
  }
  // Same options but the route: other noise too.
  SimulationOptions noisy;
  noisy.scenario = Kind::Rooms;
  noisy.route = Route::Revisit;
  const auto n1 = simulate(noisy);
  noisy.route = Route::Default;
  const auto n2 = simulate(noisy);
  EXPECT_NE(n1.steps[1].odometry->mean.x, n2.steps[1].odometry->mean.x);
  SimulationOptions none;
  none.scenario = Kind::PaperSynthetic;
  none.route = Route::Revisit;
  try {
    Simulator sim(none);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "scenario 'paper-synthetic' has no revisit route (rooms, park, corridors and "
                 "clusters have one)");
  }
}

// The worlds of another character: long corridors with few landmarks, and trees in clusters.
// Both routes read most of the world, the revisit starts elsewhere, and the readings are few a
// step (corridors) or come in bursts between blind stretches (clusters).
TEST(Simulator, CorridorsAndClustersAreSparseWorldsWithARevisit) {
  for (const Kind scenario : {Kind::Corridors, Kind::Clusters}) {
    SimulationOptions first = zeroNoise(scenario), again = zeroNoise(scenario);
    again.route = Route::Revisit;
    const auto a = simulate(first), b = simulate(again);
    EXPECT_EQ(a.ground_truth.landmarks, b.ground_truth.landmarks) << name(scenario);
    const std::size_t n = a.ground_truth.landmarks.size();
    if (scenario == Kind::Corridors) {
      EXPECT_GT(n, 90u);
      EXPECT_LT(n, 150u);
    } else {
      EXPECT_GT(n, 140u);  // 16 clusters of 6-12 trees and 24 lone ones
      EXPECT_LT(n, 220u);
    }
    const auto& start = b.ground_truth.path.front();
    EXPECT_GT(std::hypot(start.x, start.y), 20.0) << name(scenario);
    for (const auto* d : {&a, &b}) {
      std::set<LandmarkId> seen;
      std::size_t readings = 0, blind = 0;
      for (const auto& st : d->steps) {
        for (const auto& r : st.scan->readings) seen.insert(r.id);
        readings += st.scan->readings.size();
        blind += st.scan->readings.empty();
      }
      EXPECT_GT(seen.size(), 9 * n / 10) << name(scenario);
      const double per_step = static_cast<double>(readings) / static_cast<double>(d->steps.size());
      if (scenario == Kind::Corridors) {
        EXPECT_LT(per_step, 4.0) << name(scenario);  // few in view
      } else {
        EXPECT_GT(blind, d->steps.size() / 20) << name(scenario);  // blind stretches
      }
    }
  }
}

TEST(Simulator, BadOptionsAreConfigErrors) {
  const auto message = [](const std::string& text) {
    mrpt::config::CConfigFileMemory ini(text);
    SimulationOptions o;
    try {
      o.loadFromConfigFile(ini, "Sim");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("[Sim]\nscenario = moon\n"),
            "[Sim] scenario = 'moon': must be one of paper-synthetic, rooms, park, lifelong, "
            "corridors, clusters");
  EXPECT_EQ(message("[Sim]\nroute = back\n"),
            "[Sim] route = 'back': must be one of default, revisit");
  EXPECT_EQ(message("[Sim]\ndt = 0\n"), "[Sim] dt = 0: must be at least 1e-06");
  mrpt::config::CConfigFileMemory ini(
      std::string("[Sim]\nscenario = park\nseed = 7\nlaps = 2\nroute = revisit\n"
                  "with_ids = false\nsensor_std_range = 0.2\n"));
  SimulationOptions loaded;
  loaded.loadFromConfigFile(ini, "Sim");
  EXPECT_EQ(loaded.scenario, Kind::Park);
  EXPECT_EQ(loaded.scenarioName(), "park");
  EXPECT_EQ(loaded.route, Route::Revisit);
  EXPECT_EQ(loaded.seed, 7u);
  EXPECT_EQ(loaded.laps, 2);
  EXPECT_FALSE(loaded.with_ids);
  EXPECT_EQ(loaded.sensor_std_range, 0.2);
  EXPECT_EQ(loaded.odo_std_xy, -1);  // absent: the default
  std::ostringstream dump;
  loaded.dumpToTextStream(dump);
  EXPECT_NE(dump.str().find("\nscenario                 = park  // "), std::string::npos)
      << dump.str();
  EXPECT_NE(dump.str().find("\nseed                     = 7\n"), std::string::npos) << dump.str();
  // One table: what is saved loads back the same, and keys() is the table's.
  mrpt::config::CConfigFileMemory saved;
  loaded.saveToConfigFile(saved, "Again");
  SimulationOptions back;
  back.loadFromConfigFile(saved, "Again");
  EXPECT_EQ(back.scenario, Kind::Park);
  EXPECT_EQ(back.route, Route::Revisit);
  EXPECT_EQ(back.sensor_std_range, 0.2);
  EXPECT_EQ(back.odo_std_xy, -1);
  EXPECT_EQ(SimulationOptions::keys().size(), 10u);
}
