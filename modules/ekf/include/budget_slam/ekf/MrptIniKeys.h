#pragma once
#include <map>
#include <string>
#include <vector>

namespace budget_slam::ekf {

/// Keys MRPT 2.5's kf-slam understands in its sections [MappingApplication], [RangeBearingKFSLAM]
/// and [RangeBearingKFSLAM_KalmanFilter]: those its 2D and 3D filters and KFSLAMApp read, plus the
/// legacy ones MRPT's own shipped ini files still carry (stdXY_no_odo, verbose, ...), so that any
/// kf-slam ini file passes the unknown-key check.
const std::map<std::string, std::vector<std::string>>& mrptKfSlamIniKeys();

}  // namespace budget_slam::ekf
