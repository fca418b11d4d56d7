#include "budget_slam/graph/GraphOptions.h"

#include <ostream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::graph {

void GraphSlamOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                          const std::string& section) {
  const IniSection s(ini, section);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  solver = s.readChoice("solver", solver, {"gauss-newton", "levenberg-marquardt"});
  max_iterations = static_cast<int>(s.readInt("max_iterations", max_iterations, 1, 100000));
  step_tolerance = s.readDouble("step_tolerance", step_tolerance, 0, kInf);
  relative_chi2_tolerance = s.readDouble("relative_chi2_tolerance", relative_chi2_tolerance, 0, 1);
  lm_initial_lambda = s.readDouble("lm_initial_lambda", lm_initial_lambda, 0, kInf);
  lm_lambda_factor = s.readDouble("lm_lambda_factor", lm_lambda_factor, 1.0001, kInf);
  relinearize_every =
      static_cast<int>(s.readInt("relinearize_every", relinearize_every, 0, 1000000));
  incremental_iterations =
      static_cast<int>(s.readInt("incremental_iterations", incremental_iterations, 1, 1000));
  relinearize_chi2 = s.readDouble("relinearize_chi2", relinearize_chi2, 0, kInf);
  relinearize_threshold = s.readDouble("relinearize_threshold", relinearize_threshold, 0, kInf);
  reorder_fill_ratio = s.readDouble("reorder_fill_ratio", reorder_fill_ratio, 0, kInf);
  max_poses = static_cast<int>(s.readInt("max_poses", max_poses, 0, 100000000));
  if (max_poses == 1)
    throw ConfigError("[" + section + "] max_poses = 1: must be 0 (unbounded) or at least 2");
  prior_std_xy = s.readDouble("prior_std_xy", prior_std_xy, 1e-12, kInf);
  prior_std_yaw_deg = s.readDouble("prior_std_yaw_deg", prior_std_yaw_deg, 1e-12, kInf);
  no_odometry_std_xy = s.readDouble("no_odometry_std_xy", no_odometry_std_xy, 1e-12, kInf);
  no_odometry_std_yaw_deg =
      s.readDouble("no_odometry_std_yaw_deg", no_odometry_std_yaw_deg, 1e-12, kInf);
  odometry_min_std_xy = s.readDouble("odometry_min_std_xy", odometry_min_std_xy, 1e-12, kInf);
  odometry_min_std_yaw_deg =
      s.readDouble("odometry_min_std_yaw_deg", odometry_min_std_yaw_deg, 1e-12, kInf);
  exact_pose_covariance = s.readBool("exact_pose_covariance", exact_pose_covariance);
  association_gate_chi2 = s.readDouble("association_gate_chi2", association_gate_chi2, 0, kInf);
  information_gain =
      s.readChoice("information_gain", information_gain, {"marginal", "conditional"});
}

void GraphSlamOptions::dumpToTextStream(std::ostream& out) const {
  out << "[" << kSection << "]\n"
      << "solver                   = " << solver << "  // gauss-newton | levenberg-marquardt\n"
      << "max_iterations           = " << max_iterations << "  // full solve\n"
      << "step_tolerance           = " << step_tolerance << "  // [m, rad]\n"
      << "relative_chi2_tolerance  = " << relative_chi2_tolerance << "\n"
      << "lm_initial_lambda        = " << lm_initial_lambda << "\n"
      << "lm_lambda_factor         = " << lm_lambda_factor << "\n"
      << "relinearize_every        = " << relinearize_every << "  // [poses], 0 = at finish only\n"
      << "incremental_iterations   = " << incremental_iterations << "\n"
      << "relinearize_chi2         = " << relinearize_chi2 << "  // per reading, 0 = never early\n"
      << "relinearize_threshold    = " << relinearize_threshold
      << "  // [m, rad], 0 = every incremental iteration\n"
      << "reorder_fill_ratio       = " << reorder_fill_ratio
      << "  // fresh ordering when fill grows by this factor, 0 = always\n"
      << "max_poses                = " << max_poses << "  // 0 = unbounded\n"
      << "prior_std_xy             = " << prior_std_xy << "  // [m]\n"
      << "prior_std_yaw_deg        = " << prior_std_yaw_deg << "  // [deg]\n"
      << "no_odometry_std_xy       = " << no_odometry_std_xy << "  // [m]\n"
      << "no_odometry_std_yaw_deg  = " << no_odometry_std_yaw_deg << "  // [deg]\n"
      << "odometry_min_std_xy      = " << odometry_min_std_xy << "  // [m]\n"
      << "odometry_min_std_yaw_deg = " << odometry_min_std_yaw_deg << "  // [deg]\n"
      << "exact_pose_covariance    = " << (exact_pose_covariance ? "true" : "false")
      << "  // false: propagated between factorizations\n"
      << "association_gate_chi2    = " << association_gate_chi2 << "  // chi2, 2 dof\n"
      << "information_gain         = " << information_gain << "  // marginal | conditional\n";
}

std::vector<std::string> GraphSlamOptions::keys() {
  return {"solver",
          "max_iterations",
          "step_tolerance",
          "relative_chi2_tolerance",
          "lm_initial_lambda",
          "lm_lambda_factor",
          "relinearize_every",
          "incremental_iterations",
          "relinearize_chi2",
          "relinearize_threshold",
          "reorder_fill_ratio",
          "max_poses",
          "prior_std_xy",
          "prior_std_yaw_deg",
          "no_odometry_std_xy",
          "no_odometry_std_yaw_deg",
          "odometry_min_std_xy",
          "odometry_min_std_yaw_deg",
          "exact_pose_covariance",
          "association_gate_chi2",
          "information_gain"};
}

SolverSettings GraphSlamOptions::solverSettings() const {
  SolverSettings s;
  s.method = solver == "levenberg-marquardt" ? SolverSettings::Method::LevenbergMarquardt
                                             : SolverSettings::Method::GaussNewton;
  s.max_iterations = max_iterations;
  s.step_tolerance = step_tolerance;
  s.relative_chi2_tolerance = relative_chi2_tolerance;
  s.lm_initial_lambda = lm_initial_lambda;
  s.lm_lambda_factor = lm_lambda_factor;
  return s;
}

void RangeBearingNoise::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                           const std::string& section) {
  // The same rule as the EKF's (ekf::checkMrptKfSlamOptions): both read these keys.
  const IniSection s(ini, section);
  std_sensor_range = s.readStd("std_sensor_range", std_sensor_range);
  std_sensor_yaw_deg = s.readStd("std_sensor_yaw_deg", std_sensor_yaw_deg);
}

void RangeBearingNoise::dumpToTextStream(std::ostream& out) const {
  out << "[" << kSection << "] (graph backend)\n"
      << "std_sensor_range   = " << std_sensor_range << "  // [m]\n"
      << "std_sensor_yaw_deg = " << std_sensor_yaw_deg << "  // [deg]\n";
}

std::vector<std::string> RangeBearingNoise::keys() {
  return {"std_sensor_range", "std_sensor_yaw_deg"};
}

}  // namespace budget_slam::graph
