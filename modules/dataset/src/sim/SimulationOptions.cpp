#include <limits>

#include "budget_slam/dataset/Simulator.h"

namespace budget_slam::dataset {

const EnumNames<SimulationOptions::ScenarioKind>& SimulationOptions::scenarioNames() {
  static const EnumNames<ScenarioKind> n = {{"paper-synthetic", ScenarioKind::PaperSynthetic},
                                            {"rooms", ScenarioKind::Rooms},
                                            {"park", ScenarioKind::Park},
                                            {"lifelong", ScenarioKind::Lifelong},
                                            {"corridors", ScenarioKind::Corridors},
                                            {"clusters", ScenarioKind::Clusters}};
  return n;
}

const EnumNames<SimulationOptions::Route>& SimulationOptions::routeNames() {
  static const EnumNames<Route> n = {{"default", Route::Default}, {"revisit", Route::Revisit}};
  return n;
}

const OptionTable<SimulationOptions>& SimulationOptions::table() {
  using O = SimulationOptions;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  static const OptionTable<O> t = {
      option::choice("scenario", &O::scenario, scenarioNames(),
                     "paper-synthetic | rooms | park | lifelong | corridors | clusters"),
      option::integer("seed", &O::seed, 0),
      option::flag("with_ids", &O::with_ids),
      option::integer("laps", &O::laps, 0, 1000000, "0: scenario default"),
      option::choice("route", &O::route, routeNames(),
                     "default | revisit (rooms, park, corridors, clusters)"),
      option::real("odo_std_xy", &O::odo_std_xy, -kInf, kInf, "m per step; < 0: scenario default"),
      option::real("odo_std_yaw_deg", &O::odo_std_yaw_deg, -kInf, kInf,
                   "deg per step; < 0: default"),
      option::real("sensor_std_range", &O::sensor_std_range, -kInf, kInf, "m; < 0: default"),
      option::real("sensor_std_yaw_deg", &O::sensor_std_yaw_deg, -kInf, kInf, "deg; < 0: default"),
      option::real("dt", &O::dt, 1e-6, kInf, "s between steps"),
  };
  return t;
}

}  // namespace budget_slam::dataset
