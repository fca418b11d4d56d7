#include <ostream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"
#include "budget_slam/dataset/Simulator.h"

namespace budget_slam::dataset {

void SimulationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                           const std::string& section) {
  const IniSection s(ini, section);
  scenario = s.readChoice("scenario", scenario, {"paper-synthetic", "rooms", "park", "lifelong"});
  seed = static_cast<std::uint64_t>(s.readInt("seed", static_cast<long long>(seed), 0));
  with_ids = s.readBool("with_ids", with_ids);
  laps = static_cast<int>(s.readInt("laps", laps, 0, 1000000));
  route = s.readChoice("route", route, {"default", "revisit"});
  odo_std_xy = s.readDouble("odo_std_xy", odo_std_xy);
  odo_std_yaw_deg = s.readDouble("odo_std_yaw_deg", odo_std_yaw_deg);
  sensor_std_range = s.readDouble("sensor_std_range", sensor_std_range);
  sensor_std_yaw_deg = s.readDouble("sensor_std_yaw_deg", sensor_std_yaw_deg);
  dt = s.readDouble("dt", dt, 1e-6);
}

void SimulationOptions::dumpToTextStream(std::ostream& out) const {
  out << "scenario           = " << scenario << "  // paper-synthetic | rooms | park | lifelong\n"
      << "seed               = " << seed << "\n"
      << "with_ids           = " << (with_ids ? "true" : "false") << "\n"
      << "laps               = " << laps << "  // 0: scenario default\n"
      << "route              = " << route << "  // default | revisit (rooms, park)\n"
      << "odo_std_xy         = " << odo_std_xy << "  // m per step; < 0: scenario default\n"
      << "odo_std_yaw_deg    = " << odo_std_yaw_deg << "  // deg per step; < 0: default\n"
      << "sensor_std_range   = " << sensor_std_range << "  // m; < 0: default\n"
      << "sensor_std_yaw_deg = " << sensor_std_yaw_deg << "  // deg; < 0: default\n"
      << "dt                 = " << dt << "  // s between steps\n";
}

}  // namespace budget_slam::dataset
