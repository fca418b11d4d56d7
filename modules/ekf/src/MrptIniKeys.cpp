#include "budget_slam/ekf/MrptIniKeys.h"

namespace budget_slam::ekf {

const std::map<std::string, std::vector<std::string>>& mrptKfSlamIniKeys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"MappingApplication",
       {"kf_implementation", "rawlog_file", "rawlog_offset", "logOutput_dir", "SAVE_LOG_FREQUENCY",
        "SAVE_DA_LOG", "SAVE_3D_SCENES", "SAVE_MAP_REPRESENTATIONS", "SHOW_3D_LIVE",
        "CAMERA_3DSCENE_FOLLOWS_ROBOT", "ground_truth_file", "ground_truth_file_robot",
        "ground_truth_data_association", "method", "verbose"}},
      {"RangeBearingKFSLAM",
       {"stds_Q_no_odo", "std_sensor_range", "std_sensor_yaw_deg", "std_sensor_pitch_deg",
        "std_odo_z_additional", "doPartitioningExperiment", "partitioningMethod",
        "partitionThreshold", "create_simplemap", "force_ignore_odometry",
        "quantiles_3D_representation", "data_assoc_method", "data_assoc_metric",
        "data_assoc_IC_metric", "data_assoc_IC_chi2_thres", "data_assoc_IC_ml_threshold",
        "stdXY_no_odo", "stdPhi_no_odo_deg"}},
      {"RangeBearingKFSLAM_KalmanFilter",
       {"method", "verbosity_level", "IKF_iterations", "enable_profiler",
        "use_analytic_transition_jacobian", "use_analytic_observation_jacobian",
        "debug_verify_analytic_jacobians", "debug_verify_analytic_jacobians_threshold", "verbose"}},
  };
  return keys;
}

const std::vector<std::string>& mrptOtherAppSections() {
  static const std::vector<std::string> sections = {
      // simul-landmarks, simul-beacons
      "Params", "RANDOMSET_*",
      // icp-slam, icp-slam-live, rbpf-slam (their map definitions share kf-slam's app section name)
      "ICP", "LIDAR_SENSOR", "MappingApplication_*",
      // pf-localization, ro-localization
      "PF_options", "KLD_options", "MetricMap", "MetricMap_*", "LocalizationExperiment",
      "DummyOdometryParams", "OdometryEstimation", "RO_MODEL", "ro-localization",
      // hmt-slam
      "HMT-SLAM", "GRAPH_CUT", "PARTICLE_FILTER", "TLC_GRIDMATCHING", "MetricMaps", "MetricMaps_*",
      // graphslam-engine
      "GeneralConfiguration", "EdgeRegistrationDeciderParameters",
      "NodeRegistrationDeciderParameters", "OptimizerParameters", "VisualizationParameters",
      // icp-graph-slam, grid-matching
      "icp_graphslam", "icp_graphslam_*", "grid-match", "metric_maps", "metric_maps_*"};
  return sections;
}

}  // namespace budget_slam::ekf
