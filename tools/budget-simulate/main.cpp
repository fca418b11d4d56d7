// budget-simulate: a scenario world -> MRPT rawlog + ground truth + sidecar ini. All the work is
// in budget_slam::dataset (Simulator.h).
#include <tclap/CmdLine.h>

#include <cmath>
#include <iostream>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/StopSignals.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/DatasetFiles.h"
#include "budget_slam/dataset/Sessions.h"
#include "budget_slam/dataset/Simulator.h"

namespace {

/// A noise flag, when given, is a finite number >= 0 (not given: the scenario's default).
double noiseFlag(const TCLAP::ValueArg<double>& flag) {
  const double v = flag.getValue();
  if (flag.isSet() && !(std::isfinite(v) && v >= 0)) {
    std::ostringstream text;
    text << "--" << flag.getName() << " " << v << ": must be a finite number >= 0";
    throw budget_slam::UsageError(text.str());
  }
  return v;
}

/// TCLAP reads an empty value ("--change ''") as the flag's default: refused, as budget-slam
/// refuses its own (runs::refuseEmptyValue's words).
void refuseEmptyValues(const std::vector<std::string>& args,
                       const std::vector<const TCLAP::Arg*>& flags) {
  for (std::size_t i = 1; i + 1 < args.size(); ++i)
    for (const TCLAP::Arg* f : flags)
      if ((args[i] == "--" + f->getName() ||
           (!f->getFlag().empty() && args[i] == "-" + f->getFlag())) &&
          args[i + 1].empty())
        throw budget_slam::UsageError("--" + f->getName() +
                                      " '': an empty value (leave the flag out instead)");
}

/// --change-split D:M:A, three shares >= 0 (not all 0).
void parseSplit(const std::string& text, budget_slam::dataset::SessionChangeOptions& o) {
  double v[3];
  char end = 0;
  if (std::sscanf(text.c_str(), "%lf:%lf:%lf%c", &v[0], &v[1], &v[2], &end) != 3 ||
      !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) || v[0] < 0 ||
      v[1] < 0 || v[2] < 0 || v[0] + v[1] + v[2] <= 0)
    throw budget_slam::UsageError("--change-split '" + text +
                                  "': expected three shares D:M:A (disappear, move, appear), "
                                  "each >= 0, not all 0");
  o.share_disappear = v[0], o.share_move = v[1], o.share_appear = v[2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace budget_slam;
  // For the life of the process: Ctrl-C or SIGTERM ends the simulation with exit 130 and no file
  // written, a closed stdout is a failed write (core/StopSignals.h).
  const StopSignals signals(false);
  CapturedUsage usage(  // outlives cmd, which only borrows it
      "   budget-simulate --scenario rooms --seed 3 -o my_rooms.rawlog\n"
      "      the rooms world of seed 3: my_rooms.rawlog, its ground truth\n"
      "      (my_rooms_ground_truth.txt, my_rooms_ground_truth_robot_path.txt) and my_rooms.ini\n"
      "   budget-simulate --scenario rooms --seed 3 --route revisit -o my_rooms_revisit.rawlog\n"
      "      the same world along another route: a traversal to relocalize on\n"
      "   budget-simulate --scenario lifelong --laps 10 --no-ids -o long.rawlog\n"
      "      10 laps of a changing world, readings without landmark IDs\n"
      "   budget-simulate --scenario rooms --sessions 20 --change 0.05 -o life.rawlog\n"
      "      20 sessions in one world, 5% of its landmarks disappearing, moving or appearing\n"
      "      before each session after the first: life_s01.rawlog .. life_s20.rawlog, their\n"
      "      ground truth and sidecars, and life_changes.csv\n"
      "   budget-slam run -c config.ini -i my_rooms.rawlog -o OUT\n"
      "      then SLAM on it (the sidecar my_rooms.ini is read after config.ini)\n");
  try {
    TCLAP::CmdLine cmd(
        "Simulates 2D landmark SLAM data (odometry + range-bearing readings) in one of the "
        "scenarios and writes a gzip MRPT rawlog, its two ground-truth files and a sidecar .ini. "
        "The same options give the same bytes.",
        ' ', "0.1");
    using Sim = dataset::SimulationOptions;
    std::vector<std::string> names = namesOf(Sim::scenarioNames());
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
    std::vector<std::string> routes = namesOf(Sim::routeNames());
    TCLAP::ValuesConstraint<std::string> route_values(routes);
    TCLAP::ValueArg<std::string> route(
        "", "route",
        "revisit (rooms, park, corridors, clusters): the same world from another start along "
        "another route through every room or region, other noise (default: default)",
        false, "default", &route_values, cmd);
    TCLAP::ValueArg<int> sessions(
        "", "sessions",
        "N sessions in one world that changes between them: one rawlog a session, "
        "<out>_s01.rawlog ..., and <out>_changes.csv (1 to 999)",
        false, 0, "N", cmd);
    TCLAP::ValueArg<double> change("", "change",
                                   "with --sessions: share of the landmarks that change before "
                                   "each session after the first, in [0, 1] (default 0.05)",
                                   false, 0.05, "F", cmd);
    TCLAP::ValueArg<std::string> change_split(
        "", "change-split",
        "with --sessions: shares of the changes that disappear, move and appear (default 1:1:1)",
        false, "1:1:1", "D:M:A", cmd);
    TCLAP::ValueArg<double> move_distance(
        "", "move-distance",
        "with --sessions: how far a landmark moves, and how far from a landmark a new one "
        "appears [m] (default 1)",
        false, 1.0, "M", cmd);
    TCLAP::SwitchArg joined("", "joined",
                            "with --sessions: one traversal, <out> itself, driving the sessions "
                            "back to back (the world changes as each begins)",
                            cmd);
    TCLAP::SwitchArg zero_noise("", "zero-noise", "no odometry or sensor noise at all", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "output rawlog (name ends in .rawlog)", true, "",
                                     "out.rawlog", cmd);
    TCLAP::SwitchArg force("", "force",
                           "write even where an output file exists: it is kept as <name>.~N~ "
                           "(nothing is deleted)",
                           cmd);
    cmd.setExceptionHandling(false);
    cmd.setOutput(&usage);
    std::vector<std::string> args(argv, argv + argc);
    args[0] = "budget-simulate";  // the usage names the program, not the path it was run by
    refuseEmptyValues(args, {&scenario, &seed, &laps, &odo_xy, &odo_yaw, &std_range, &std_yaw,
                             &route, &sessions, &change, &change_split, &move_distance, &out});
    cmd.parse(args);

    Sim o;  // the constraints above admit only names of the tables: valueOf finds each
    o.scenario = *valueOf(Sim::scenarioNames(), scenario.getValue());
    o.seed = seed.getValue();
    o.with_ids = !no_ids.getValue();
    if (laps.getValue() < 0)
      throw UsageError("--laps " + std::to_string(laps.getValue()) +
                       ": must be at least 1 (0: the scenario's default)");
    o.laps = laps.getValue();
    o.route = *valueOf(Sim::routeNames(), route.getValue());
    o.odo_std_xy = zero_noise.getValue() ? 0 : noiseFlag(odo_xy);
    o.odo_std_yaw_deg = zero_noise.getValue() ? 0 : noiseFlag(odo_yaw);
    o.sensor_std_range = zero_noise.getValue() ? 0 : noiseFlag(std_range);
    o.sensor_std_yaw_deg = zero_noise.getValue() ? 0 : noiseFlag(std_yaw);
    try {
      dataset::checkRawlogName(out.getValue());
    } catch (const Error& e) {
      throw UsageError(e.what());
    }
    if (!sessions.isSet()) {
      for (const TCLAP::Arg* a : std::initializer_list<const TCLAP::Arg*>{&change, &change_split,
                                                                          &move_distance, &joined})
        if (a->isSet()) throw UsageError("--" + a->getName() + " needs --sessions N");
    } else {
      dataset::SessionChangeOptions so;
      so.sessions = sessions.getValue();
      so.change = change.getValue();
      parseSplit(change_split.getValue(), so);
      so.move_distance = move_distance.getValue();
      so.joined = joined.getValue();
      for (const auto& w : dataset::simulateSessionsToFiles(o, so, out.getValue()))
        std::cout << w.path
                  << (w.steps ? ": " + std::to_string(w.steps) + " steps of scenario " +
                                    o.scenarioName()
                              : std::string(": the changes"))
                  << "\n";
      // A closed stdout is a failed run, as in the single-rawlog mode (the files stay: they
      // were written whole).
      return flushStdout(std::cout, std::cerr, "budget-simulate") ? kExitOk : kExitFailed;
    }
    dataset::checkOutputFiles(out.getValue(), {}, force.getValue());  // before the simulation
    const auto steps = dataset::simulateToFiles(o, out.getValue(), force.getValue());
    std::cout << out.getValue() << ": " << steps << " steps of scenario " << o.scenarioName()
              << "\n";
    return flushStdout(std::cout, std::cerr, "budget-simulate") ? kExitOk : kExitFailed;
  } catch (const TCLAP::ExitException& e) {
    std::cout << usage.text;  // --help or --version, once
    return flushStdout(std::cout, std::cerr, "budget-simulate") ? kExitOk : kExitFailed;
  } catch (const Interrupted& e) {
    std::cerr << "budget-simulate: " << e.what() << "; nothing written\n";
    return kExitInterrupted;
  } catch (const TCLAP::ArgException& e) {
    std::cerr << "budget-simulate: " << describe(e) << "; see budget-simulate --help\n";
    return kExitBadCommandLine;
  } catch (const budget_slam::ConfigError& e) {
    // Every option comes from the command line: a bad one is a bad command line.
    std::cerr << "budget-simulate: " << e.what() << "; see budget-simulate --help\n";
    return kExitBadCommandLine;
  } catch (const std::exception& e) {
    std::cerr << "budget-simulate: " << failureLine(e) << "\n";
    return kExitFailed;
  }
}
