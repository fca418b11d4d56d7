#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "World.h"
#include "budget_slam/dataset/SensorNoise.h"
#include "budget_slam/dataset/Simulator.h"

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
  /// The "revisit" route (--route revisit): a second traversal of the same world, from another
  /// start, through every room or region (empty: the scenario has none).
  Eigen::Vector2d revisit_start = Eigen::Vector2d::Zero();  ///< [m]
  double revisit_start_yaw = 0;                             ///< [rad]
  std::vector<Eigen::Vector2d> revisit_route;               ///< waypoints [m]
};

/// The scenario `kind`; its landmarks are drawn with `seed`. `laps` (> 0) overrides the
/// scenario's default; for lifelong the world changes between laps. Route::Revisit (rooms and
/// park): the same world in the same frame (the default route's start pose at the origin), driven
/// from the revisit start along the revisit route; a ConfigError for a scenario without one.
Scenario makeScenario(SimulationOptions::ScenarioKind kind, std::uint64_t seed, int laps,
                      SimulationOptions::Route route = SimulationOptions::Route::Default);

}  // namespace budget_slam::dataset::sim
