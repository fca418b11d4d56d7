#include "budget_slam/graph/GraphOptions.h"

#include <limits>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::graph {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// max_poses: 0 (unbounded) or at least 2 (one pose left would carry only its prior).
OptionKey<GraphSlamOptions> maxPosesKey() {
  const OptionKey<GraphSlamOptions> k =
      option::integer("max_poses", &GraphSlamOptions::max_poses, 0, 100000000, "0 = unbounded");
  return {k.name,
          [read = k.read](GraphSlamOptions& o, const IniSection& s) {
            read(o, s);
            if (o.max_poses == 1)
              throw KeyError(
                  s.name(), "max_poses",
                  "[" + s.name() + "] max_poses = 1: must be 0 (unbounded) or at least 2");
          },
          k.text, k.doc};
}

}  // namespace

const EnumNames<SolverSettings::Method>& GraphSlamOptions::solverNames() {
  static const EnumNames<SolverSettings::Method> n = {
      {"gauss-newton", SolverSettings::Method::GaussNewton},
      {"levenberg-marquardt", SolverSettings::Method::LevenbergMarquardt}};
  return n;
}

const EnumNames<GraphSlamOptions::InformationGain>& GraphSlamOptions::informationGainNames() {
  static const EnumNames<InformationGain> n = {{"marginal", InformationGain::Marginal},
                                               {"conditional", InformationGain::Conditional}};
  return n;
}

const OptionTable<GraphSlamOptions>& GraphSlamOptions::table() {
  using O = GraphSlamOptions;
  using S = SolverSettings;
  // Table order is reading order: the first bad value of a section is the one reported.
  static const OptionTable<O> t = {
      option::within(&O::solver, option::choice("solver", &S::method, solverNames(),
                                                "gauss-newton | levenberg-marquardt")),
      option::within(&O::solver, option::integer("max_iterations", &S::max_iterations, 1, 100000,
                                                 "iterations of a full solve")),
      option::within(&O::solver,
                     option::real("step_tolerance", &S::step_tolerance, 0, kInf, "[m, rad]")),
      option::within(&O::solver, option::real("relative_chi2_tolerance",
                                              &S::relative_chi2_tolerance, 0, 1, "0 = off")),
      option::within(&O::solver, option::real("lm_initial_lambda", &S::lm_initial_lambda, 0, kInf,
                                              "x diag(H)")),
      option::within(&O::solver, option::real("lm_lambda_factor", &S::lm_lambda_factor, 1.0001,
                                              kInf, "on reject / on accept")),
      option::integer("relinearize_every", &O::relinearize_every, 0, 1000000,
                      "[poses], 0 = at finish only"),
      option::integer("incremental_iterations", &O::incremental_iterations, 1, 1000),
      option::real("relinearize_chi2", &O::relinearize_chi2, 0, kInf,
                   "per reading, 0 = never early"),
      option::real("relinearize_threshold", &O::relinearize_threshold, 0, kInf,
                   "[m, rad], a variable takes its step past this, 0 = every step"),
      option::real("wildfire_threshold", &O::wildfire_threshold, 0, kInf,
                   "[m, rad], a row's change below this does not spread, 0 = every change"),
      option::real("reorder_fill_ratio", &O::reorder_fill_ratio, 0, kInf,
                   "fresh ordering when fill grows by this factor, <= 1 = at every change"),
      maxPosesKey(),
      option::real("prior_std_xy", &O::prior_std_xy, 1e-12, kInf, "[m]"),
      option::real("prior_std_yaw_deg", &O::prior_std_yaw_deg, 1e-12, kInf, "[deg]"),
      option::real("no_odometry_std_xy", &O::no_odometry_std_xy, 1e-12, kInf, "[m]"),
      option::real("no_odometry_std_yaw_deg", &O::no_odometry_std_yaw_deg, 1e-12, kInf, "[deg]"),
      option::real("odometry_min_std_xy", &O::odometry_min_std_xy, 1e-12, kInf, "[m]"),
      option::real("odometry_min_std_yaw_deg", &O::odometry_min_std_yaw_deg, 1e-12, kInf, "[deg]"),
      option::flag("exact_pose_covariance", &O::exact_pose_covariance,
                   "false: propagated between factorizations"),
      option::real("association_gate_chi2", &O::association_gate_chi2, 0, kInf, "chi2, 2 dof"),
      option::choice("information_gain", &O::information_gain, informationGainNames(),
                     "marginal | conditional"),
  };
  return t;
}

const OptionTable<RangeBearingNoise>& RangeBearingNoise::table() {
  using O = RangeBearingNoise;
  static const OptionTable<O> t = {
      option::stddev("std_sensor_range", &O::std_sensor_range, "[m]"),
      option::stddev("std_sensor_yaw_deg", &O::std_sensor_yaw_deg, "[deg]"),
  };
  return t;
}

}  // namespace budget_slam::graph
