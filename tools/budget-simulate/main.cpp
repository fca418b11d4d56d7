// budget-simulate: a scenario world -> MRPT rawlog + ground truth + sidecar ini. All the work is
// in budget_slam::dataset (Simulator.h).
#include <tclap/CmdLine.h>

#include <iostream>

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/Simulator.h"

int main(int argc, char** argv) {
  using namespace budget_slam;
  try {
    TCLAP::CmdLine cmd(
        "Simulates 2D landmark SLAM data (odometry + range-bearing readings) in one of the "
        "scenarios and writes a gzip MRPT rawlog, its two ground-truth files and a sidecar .ini. "
        "The same options give the same bytes.",
        ' ', "0.1");
    std::vector<std::string> names = {"paper-synthetic", "rooms", "park", "lifelong"};
    TCLAP::ValuesConstraint<std::string> name_values(names);
    TCLAP::ValueArg<std::string> scenario("s", "scenario", "scenario", true, "", &name_values, cmd);
    TCLAP::ValueArg<std::uint64_t> seed("", "seed", "random seed (default 1)", false, 1, "S", cmd);
    TCLAP::SwitchArg no_ids("", "no-ids", "readings carry no landmark ID", cmd);
    TCLAP::ValueArg<int> laps("", "laps",
                              "laps of the route (lifelong: the world changes between "
                              "laps; default: scenario's)",
                              false, 0, "K", cmd);
    TCLAP::ValueArg<double> odo_xy("", "odo-std-xy", "odometry noise per step, x and y [m]", false,
                                   -1, "M", cmd);
    TCLAP::ValueArg<double> odo_yaw("", "odo-std-yaw-deg", "odometry noise per step [deg]", false,
                                    -1, "DEG", cmd);
    TCLAP::ValueArg<double> std_range("", "sensor-std-range", "range noise [m]", false, -1, "M",
                                      cmd);
    TCLAP::ValueArg<double> std_yaw("", "sensor-std-yaw-deg", "bearing noise [deg]", false, -1,
                                    "DEG", cmd);
    std::vector<std::string> routes = {"default", "revisit"};
    TCLAP::ValuesConstraint<std::string> route_values(routes);
    TCLAP::ValueArg<std::string> route(
        "", "route",
        "revisit (rooms, park): the same world from another start along another route through "
        "every room or region, other noise (default: default)",
        false, "default", &route_values, cmd);
    TCLAP::SwitchArg zero_noise("", "zero-noise", "no odometry or sensor noise at all", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "output rawlog (name ends in .rawlog)", true, "",
                                     "out.rawlog", cmd);
    cmd.setExceptionHandling(false);
    cmd.parse(argc, argv);

    dataset::SimulationOptions o;
    o.scenario = scenario.getValue();
    o.seed = seed.getValue();
    o.with_ids = !no_ids.getValue();
    if (laps.getValue() < 0) throw ConfigError("--laps must be at least 1");
    o.laps = laps.getValue();
    o.route = route.getValue();
    o.odo_std_xy = zero_noise.getValue() ? 0 : odo_xy.getValue();
    o.odo_std_yaw_deg = zero_noise.getValue() ? 0 : odo_yaw.getValue();
    o.sensor_std_range = zero_noise.getValue() ? 0 : std_range.getValue();
    o.sensor_std_yaw_deg = zero_noise.getValue() ? 0 : std_yaw.getValue();
    const auto steps = dataset::simulateToFiles(o, out.getValue());
    std::cout << out.getValue() << ": " << steps << " steps of scenario " << o.scenario << "\n";
    return 0;
  } catch (const TCLAP::ExitException& e) {
    return e.getExitStatus();
  } catch (const TCLAP::ArgException& e) {
    std::cerr << "budget-simulate: " << e.error() << " (" << e.argId() << "); see --help\n";
    return 2;
  } catch (const budget_slam::Error& e) {
    std::cerr << "budget-simulate: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::string what = e.what();
    std::cerr << "budget-simulate: internal error: " << what.substr(0, what.find('\n')) << "\n";
    return 3;
  }
}
