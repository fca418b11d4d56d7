#include "budget_slam/dataset/SidecarIni.h"

#include <cmath>
#include <cstdio>

namespace budget_slam::dataset {
namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v == 0 ? 0.0 : v);
  return buf;
}

double deg(double rad) { return rad * 180.0 / M_PI; }

}  // namespace

std::string sidecarIniPathFor(const std::string& rawlog) {
  const auto slash = rawlog.find_last_of('/');
  const auto dot = rawlog.find_last_of('.');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash + 1))
    return rawlog.substr(0, dot) + ".ini";
  return rawlog + ".ini";
}

std::string sidecarIniText(const SensorNoise& noise, const std::vector<std::string>& notes) {
  std::string s;
  s += "# Sidecar ini of a rawlog: the sensor noise and limits it was made with.\n";
  s += "# budget-slam reads it after config.ini when it sits next to the rawlog.\n";
  for (const auto& n : notes) s += "# " + n + "\n";
  const auto& p = noise.sensor_pose_on_robot;
  s += "#\n";
  s += "# Sensor limits (facts about the data, not filter settings):\n";
  s += "#   min_range = " + num(noise.min_range) + " m, max_range = " + num(noise.max_range) +
       " m, fov_yaw = " + num(deg(noise.fov_yaw)) + " deg\n";
  s += "#   sensor pose on the robot: x = " + num(p.x) + " m, y = " + num(p.y) +
       " m, z = " + num(p.z) + " m, yaw = " + num(deg(p.yaw)) + " deg\n";
  s += "\n[RangeBearingKFSLAM]\n";
  s += "std_sensor_range   = " + num(noise.std_range) + "  // m, 1 sigma\n";
  s += "std_sensor_yaw_deg = " + num(deg(noise.std_yaw)) + "  // deg, 1 sigma\n";
  return s;
}

}  // namespace budget_slam::dataset
