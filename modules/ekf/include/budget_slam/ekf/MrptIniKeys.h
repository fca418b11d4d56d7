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

/// Sections of MRPT 2.5's other SLAM, localization and simulation applications, as their shipped
/// ini files name them (simul-landmarks, simul-beacons, icp-slam, rbpf-slam, pf-localization,
/// ro-localization, hmt-slam, graphslam-engine, icp-graph-slam, grid-matching). An ini shared
/// with one of them passes the unknown-section check; budget-slam reads none of them. A name
/// ending in '*' stands for every section starting with what precedes it (numbered sets, map
/// definitions).
const std::vector<std::string>& mrptOtherAppSections();

}  // namespace budget_slam::ekf
