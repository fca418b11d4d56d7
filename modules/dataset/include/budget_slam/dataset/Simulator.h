#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/ConvertedDataset.h"

namespace budget_slam::dataset {

namespace sim {
struct Scenario;
}

/// Which landmarks of a world exist when (sim::Landmark::first_lap .. last_lap count epochs): by
/// default the epoch is the lap (the lifelong scenario's changes between laps); a session of a
/// changing world (Sessions.h) stays in one epoch, and a joined traversal of sessions moves to the
/// next epoch every `laps_per_epoch` laps.
struct EpochSchedule {
  int fixed = -1;          ///< >= 0: every lap is in this epoch
  int laps_per_epoch = 0;  ///< > 0: epoch = lap / laps_per_epoch (when fixed < 0)
  /// Noise stream of the run: 0 = the route's (default 1, revisit 2); sessions after the first
  /// take their own so that no two sessions share noise.
  std::uint64_t noise_stream = 0;
  int epochOf(int lap) const {
    return fixed >= 0 ? fixed : laps_per_epoch > 0 ? lap / laps_per_epoch : lap;
  }
};

/// Options of the scenario simulator (budget-simulate), MRPT's CLoadableOptions pattern with every
/// key defined once in table() (loading, the dump and keys() follow from it). Noise values below
/// 0 mean "the scenario's default" (docs/DATASETS.md lists them).
struct SimulationOptions : public TabledOptions<SimulationOptions> {
  /// The section name of the dump; budget-simulate takes these options from its command line.
  static constexpr const char* kSection = "Simulation";

  /// The worlds of docs/DATASETS.md; ini and command-line names in scenarioNames().
  enum class ScenarioKind { PaperSynthetic, Rooms, Park, Lifelong, Corridors, Clusters };
  /// default: the scenario's route; revisit (rooms, park, corridors, clusters): the same world
  /// (same seed, landmarks, ids and frame) driven from another start along another route through
  /// every room or region, with another noise stream: a second traversal to relocalize on.
  enum class Route { Default, Revisit };

  ScenarioKind scenario = ScenarioKind::Rooms;  ///< paper-synthetic | rooms | park | lifelong |
                                                ///< corridors | clusters
  std::uint64_t seed = 1;          ///< seed of the world and of the noise; same seed, same bytes
  bool with_ids = true;            ///< false: readings carry no landmark ID (--no-ids)
  int laps = 0;                    ///< laps of the route; 0: scenario default (lifelong: 2)
  Route route = Route::Default;    ///< default | revisit
  double odo_std_xy = -1;          ///< odometry noise per step, x and y [m]; < 0: default
  double odo_std_yaw_deg = -1;     ///< odometry noise per step [deg]; < 0: default
  double sensor_std_range = -1;    ///< range noise [m]; < 0: default
  double sensor_std_yaw_deg = -1;  ///< bearing noise [deg]; < 0: default
  double dt = 1.0;                 ///< time between steps [s], > 0; step k is at t = (k + 1) dt

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<SimulationOptions>& table();
  /// The names of the scenarios and routes, in the order the help and errors list them.
  static const EnumNames<ScenarioKind>& scenarioNames();
  static const EnumNames<Route>& routeNames();
  const std::string& scenarioName() const { return nameOf(scenarioNames(), scenario); }
  const std::string& routeName() const { return nameOf(routeNames(), route); }
};

/// Drives a robot through a scenario world: Gaussian odometry noise on each true increment (x, y,
/// yaw; the rawlog states the covariance of that noise), range-bearing readings of the landmarks
/// in range and field of view that no wall hides, with Gaussian range and bearing noise.
/// Deterministic: std::mt19937_64 with our own normal sampling.
class Simulator {
 public:
  /// ConfigError for a bad option (a revisit route the scenario does not have, dt <= 0).
  explicit Simulator(const SimulationOptions& options);
  /// Drives `scenario` (made by makeScenario with `options`, then changed: Sessions.cpp) under
  /// `epochs`.
  Simulator(const SimulationOptions& options, const sim::Scenario& scenario,
            const EpochSchedule& epochs);
  ~Simulator();

  /// Simulates every step, handing each to `sink` (streaming: lifelong runs are long). The
  /// ground-truth path is complete when it returns.
  void run(const std::function<void(const Step&)>& sink);

  /// Every landmark that ever exists, and the true path (start pose, then one pose a step).
  const GroundTruth& groundTruth() const;
  /// The sensor and noise the readings are made with, as the sidecar ini states it: a standard
  /// deviation below 1e-4 (m, rad; zero noise included) is stated as 1e-4, as the rawlog's
  /// odometry covariance states at least 1e-6 (budget-slam refuses a zero one, and its EKF
  /// diverges on a range noise of 1e-6 m).
  SensorNoise noise() const;
  /// Lines for the sidecar ini header.
  std::vector<std::string> notes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The whole simulation in memory.
ConvertedDataset simulate(const SimulationOptions& options);

/// Simulates straight into `rawlog` + its ground-truth files + sidecar ini, without holding the
/// steps in memory; the files appear together when all are written, and never replace one that
/// exists (saveDatasetFiles: `force` keeps it as a numbered backup). A stop request (Ctrl-C) ends
/// it between two steps with Interrupted, leaving no file. Returns the number of steps written.
std::size_t simulateToFiles(const SimulationOptions& options, const std::string& rawlog,
                            bool force = false);

}  // namespace budget_slam::dataset
