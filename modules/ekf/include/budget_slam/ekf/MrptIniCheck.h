#pragma once
#include <mrpt/config/CConfigFileBase.h>

namespace budget_slam::ekf {

/// Checks every value MRPT 2.5's CRangeBearingKFSLAM2D::loadOptions reads from
/// [RangeBearingKFSLAM] and [RangeBearingKFSLAM_KalmanFilter], before MRPT reads it: MRPT parses
/// numbers with atof (so "abc" is 0, "1e39" an infinite float), stores the sensor noise as 32-bit
/// floats, and fails on a bad enum or a vector of the wrong length with a stack dump. Each failure
/// is a ConfigError naming section, key and value, e.g.
///   "[RangeBearingKFSLAM] std_sensor_range = 0: must be > 0 (a standard deviation)".
/// Checked: std_sensor_range, std_sensor_yaw_deg (finite, > 0, within IniSection::readStd's
/// range), stds_Q_no_odo (3 finite values >= 0: x, y [m], yaw [deg]), quantiles_3D_representation
/// (> 0), create_simplemap (true, false, yes, no, 0, 1), data_assoc_method (assocNN, assocJCBB),
/// data_assoc_metric and data_assoc_IC_metric (metricMaha, metricML), data_assoc_IC_chi2_thres
/// (in (0, 1)), data_assoc_IC_ml_threshold (finite); method (kfEKFNaive, kfEKFAlaDavison,
/// kfIKFFull: MRPT 2.5 does not implement kfIKF), verbosity_level (LVL_DEBUG, LVL_INFO, LVL_WARN,
/// LVL_ERROR), IKF_iterations (1 to 1000), the four boolean switches, and
/// debug_verify_analytic_jacobians_threshold (finite, > 0). Enums also take MRPT's numeric form
/// (0, 1, ...).
void checkMrptKfSlamOptions(const mrpt::config::CConfigFileBase& ini);

}  // namespace budget_slam::ekf
