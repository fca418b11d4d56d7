#pragma once
#include <string>
#include <vector>

#include "budget_slam/dataset/SensorNoise.h"

namespace budget_slam::dataset {

/// `<dir>/<stem>.ini` next to `<dir>/<stem>.rawlog`.
std::string sidecarIniPathFor(const std::string& rawlog);

/// The sidecar ini text: a comment header (`notes`, one `# ` line each: what made the rawlog and
/// how) and the MRPT keys budget-slam reads after config.ini:
///   [RangeBearingKFSLAM] std_sensor_range (m), std_sensor_yaw_deg (deg).
/// The sensor limits and pose are written as comments: they are facts about the data, not
/// settings of MRPT's filter.
std::string sidecarIniText(const SensorNoise& noise, const std::vector<std::string>& notes);

}  // namespace budget_slam::dataset
