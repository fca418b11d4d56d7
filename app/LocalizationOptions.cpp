#include "LocalizationOptions.h"

#include <ostream>

#include "budget_slam/core/IniSection.h"

namespace budget_slam::app {

void LocalizationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                             const std::string& section) {
  const IniSection s(ini, section);
  lost_threshold = s.readDouble("lost_threshold", lost_threshold, 1e-9, 1e9);
  start_std_xy = s.readDouble("start_std_xy", start_std_xy, 0, 1e6);
  start_std_yaw_deg = s.readDouble("start_std_yaw_deg", start_std_yaw_deg, 0, 360);
  gate_chi2 = s.readDouble("gate_chi2", gate_chi2, 0, 1e12);
  max_map_landmarks = static_cast<std::size_t>(
      s.readInt("max_map_landmarks", static_cast<long long>(max_map_landmarks), 0, 20000));
  max_steps = static_cast<std::size_t>(s.readInt("max_steps", 0, 0));
}

void LocalizationOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [" << kSection << "] ------------\n";
  out << "lost_threshold           = " << lost_threshold << "\n";
  out << "start_std_xy             = " << start_std_xy << "\n";
  out << "start_std_yaw_deg        = " << start_std_yaw_deg << "\n";
  out << "gate_chi2                = " << gate_chi2 << "\n";
  out << "max_map_landmarks        = " << max_map_landmarks << "\n";
  out << "max_steps                = " << max_steps << "\n";
}

std::vector<std::string> LocalizationOptions::keys() {
  return {"lost_threshold", "start_std_xy",      "start_std_yaw_deg",
          "gate_chi2",      "max_map_landmarks", "max_steps"};
}

}  // namespace budget_slam::app
