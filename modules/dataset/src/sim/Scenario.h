#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "World.h"
#include "budget_slam/dataset/SensorNoise.h"

namespace budget_slam::dataset::sim {

/// A simulated world and the route the robot drives through it, with the default sensor and
/// odometry noise of the scenario.
struct Scenario {
  std::string name;
  std::string description;  ///< one line, for the sidecar ini
  World world;
  Eigen::Vector2d start;               ///< [m]
  double start_yaw = 0;                ///< [rad]
  std::vector<Eigen::Vector2d> route;  ///< waypoints of one lap [m]
  double step = 0.3;                   ///< distance driven per step [m]
  double max_turn = 0.5;               ///< largest heading change per step [rad]
  int laps = 1;                        ///< default number of laps
  double change_fraction = 0;          ///< landmarks replaced between laps (lifelong)
  SensorNoise sensor;                  ///< limits, pose on the robot and default noise
  double odo_std_xy = 0;               ///< default odometry noise per step, x and y [m]
  double odo_std_yaw = 0;              ///< default odometry noise per step [rad]
};

/// The scenario `name` (paper-synthetic, rooms, park, lifelong); its landmarks are drawn with
/// `seed`. `laps` (> 0) overrides the scenario's default; for lifelong the world changes between
/// laps. An unknown name is a ConfigError listing the known ones.
Scenario makeScenario(const std::string& name, std::uint64_t seed, int laps);

/// Names of the scenarios, in the order the help lists them.
std::vector<std::string> scenarioNames();

}  // namespace budget_slam::dataset::sim
