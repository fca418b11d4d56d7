// Values of MRPT's own kf-slam sections are checked before MRPT reads them (ekf/MrptIniCheck.h).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "budget_slam/core/Error.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/ekf/MrptIniCheck.h"

using namespace budget_slam;

namespace {

std::string errorWith(const std::string& section, const std::string& line) {
  mrpt::config::CConfigFileMemory ini("[" + section + "]\n" + line + "\n");
  try {
    ekf::checkMrptKfSlamOptions(ini);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

const std::string kSlam = "RangeBearingKFSLAM", kKf = "RangeBearingKFSLAM_KalmanFilter";

}  // namespace

TEST(MrptIniCheck, SensorStdsAreFiniteAndPositive) {
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = 0.1 // m"), "no error");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = 0"),
            "[RangeBearingKFSLAM] std_sensor_range = 0: must be > 0 (a standard deviation)");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = -0.1"),
            "[RangeBearingKFSLAM] std_sensor_range = -0.1: must be > 0 (a standard deviation)");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range ="),
            "[RangeBearingKFSLAM] std_sensor_range = '': not a number");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = nan"),
            "[RangeBearingKFSLAM] std_sensor_range = 'nan': not a number");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = inf"),
            "[RangeBearingKFSLAM] std_sensor_range = inf: must be a finite number");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = 1e-200"),
            "[RangeBearingKFSLAM] std_sensor_range = 1e-200: must be at least 1e-12");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_range = 1e39"),
            "[RangeBearingKFSLAM] std_sensor_range = 1e39: must be at most 1e+12");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_yaw_deg = 0"),
            "[RangeBearingKFSLAM] std_sensor_yaw_deg = 0: must be > 0 (a standard deviation)");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_yaw_deg = NaN"),
            "[RangeBearingKFSLAM] std_sensor_yaw_deg = 'NaN': not a number");
  EXPECT_EQ(errorWith(kSlam, "std_sensor_yaw_deg = 0.5abc"),
            "[RangeBearingKFSLAM] std_sensor_yaw_deg = '0.5abc': not a number");
}

TEST(MrptIniCheck, StdsQNoOdoIsThreeValuesAtLeastZero) {
  const std::string why =
      ": must be 3 values (x [m], y [m], yaw [deg]), each finite and >= 0 (the motion noise of a "
      "step without odometry)";
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = 0.1 0.1 2"), "no error");
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = [0.1, 0, 2]"), "no error");
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = 0.1 0.1"),
            "[RangeBearingKFSLAM] stds_Q_no_odo = '0.1 0.1'" + why);
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = 0.1 0.1 2 4"),
            "[RangeBearingKFSLAM] stds_Q_no_odo = '0.1 0.1 2 4'" + why);
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = 0.1 -0.1 2"),
            "[RangeBearingKFSLAM] stds_Q_no_odo = '0.1 -0.1 2'" + why);
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = 0.1 nan 2"),
            "[RangeBearingKFSLAM] stds_Q_no_odo = '0.1 nan 2'" + why);
  EXPECT_EQ(errorWith(kSlam, "stds_Q_no_odo = 0.1 x 2"),
            "[RangeBearingKFSLAM] stds_Q_no_odo = '0.1 x 2'" + why);
}

TEST(MrptIniCheck, EnumsAreFromTheirList) {
  EXPECT_EQ(errorWith(kKf, "method = kfEKFAlaDavison"), "no error");
  EXPECT_EQ(errorWith(kKf, "method = 2"), "no error");
  EXPECT_EQ(errorWith(kKf, "method = bogus"),
            "[RangeBearingKFSLAM_KalmanFilter] method = 'bogus': must be one of kfEKFNaive, "
            "kfEKFAlaDavison, kfIKFFull");
  EXPECT_EQ(errorWith(kKf, "method = 7"),
            "[RangeBearingKFSLAM_KalmanFilter] method = '7': must be one of kfEKFNaive, "
            "kfEKFAlaDavison, kfIKFFull");
  EXPECT_EQ(errorWith(kKf, "method = kfIKF"),
            "[RangeBearingKFSLAM_KalmanFilter] method = 'kfIKF': MRPT 2.5 does not implement "
            "kfIKF; use kfEKFNaive, kfEKFAlaDavison or kfIKFFull");
  EXPECT_EQ(errorWith(kKf, "verbosity_level = LOUD"),
            "[RangeBearingKFSLAM_KalmanFilter] verbosity_level = 'LOUD': must be one of LVL_DEBUG, "
            "LVL_INFO, LVL_WARN, LVL_ERROR");
  EXPECT_EQ(errorWith(kSlam, "data_assoc_method = assocJCBB"), "no error");
  EXPECT_EQ(errorWith(kSlam, "data_assoc_method = nearest"),
            "[RangeBearingKFSLAM] data_assoc_method = 'nearest': must be one of assocNN, "
            "assocJCBB");
  EXPECT_EQ(errorWith(kSlam, "data_assoc_metric = metricL2"),
            "[RangeBearingKFSLAM] data_assoc_metric = 'metricL2': must be one of metricMaha, "
            "metricML");
  EXPECT_EQ(errorWith(kSlam, "data_assoc_IC_metric = 5"),
            "[RangeBearingKFSLAM] data_assoc_IC_metric = '5': must be one of metricMaha, metricML");
}

TEST(MrptIniCheck, OtherNumbersAndSwitches) {
  EXPECT_EQ(errorWith(kSlam, "data_assoc_IC_chi2_thres = 1"),
            "[RangeBearingKFSLAM] data_assoc_IC_chi2_thres = 1: must be in (0, 1) (a confidence "
            "level)");
  EXPECT_EQ(errorWith(kSlam, "data_assoc_IC_ml_threshold = inf"),
            "[RangeBearingKFSLAM] data_assoc_IC_ml_threshold = inf: must be a finite number");
  EXPECT_EQ(errorWith(kSlam, "quantiles_3D_representation = 0"),
            "[RangeBearingKFSLAM] quantiles_3D_representation = 0: must be at least 1e-06");
  EXPECT_EQ(errorWith(kSlam, "create_simplemap = maybe"),
            "[RangeBearingKFSLAM] create_simplemap = 'maybe': not a boolean (true or false)");
  EXPECT_EQ(errorWith(kKf, "IKF_iterations = 0"),
            "[RangeBearingKFSLAM_KalmanFilter] IKF_iterations = 0: must be at least 1");
  EXPECT_EQ(errorWith(kKf, "enable_profiler = on"),
            "[RangeBearingKFSLAM_KalmanFilter] enable_profiler = 'on': not a boolean (true or "
            "false)");
  EXPECT_EQ(errorWith(kKf, "debug_verify_analytic_jacobians_threshold = -1"),
            "[RangeBearingKFSLAM_KalmanFilter] debug_verify_analytic_jacobians_threshold = -1: "
            "must be > 0");
}

TEST(MrptIniCheck, TheBackendRefusesBadValuesInOneLine) {
  mrpt::config::CConfigFileMemory ini("[RangeBearingKFSLAM_KalmanFilter]\nmethod = bogus\n");
  try {
    ekf::EkfBackend b(ini);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory ok("[RangeBearingKFSLAM]\nstd_sensor_range = 0.05\n");
  EXPECT_NO_THROW(ekf::EkfBackend b(ok));
}
