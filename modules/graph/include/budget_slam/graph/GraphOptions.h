#pragma once
#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

#include "budget_slam/graph/Solver.h"

namespace budget_slam::graph {

/// [GraphSLAM]: the landmark graph backend (docs/GRAPH.md), MRPT's CLoadableOptions
/// pattern. Read with budget_slam::IniSection: a bad value is a ConfigError naming the key.
struct GraphSlamOptions : public mrpt::config::CLoadableOptions {
  static constexpr const char* kSection = "GraphSLAM";

  std::string solver = "gauss-newton";  ///< gauss-newton | levenberg-marquardt
  int max_iterations = 100;             ///< iterations of a full solve (finish(), optimize())
  double step_tolerance = 1e-10;        ///< converged when max |dx| < this [m, rad]
  double relative_chi2_tolerance = 0;   ///< ...or chi2 drops by less than this fraction (0: off)
  double lm_initial_lambda = 1e-5;      ///< Levenberg-Marquardt initial damping (x diag H)
  double lm_lambda_factor = 10.0;       ///< damping multiplier on reject / divisor on accept

  /// Incremental schedule: after every `relinearize_every` new poses, or as soon as a step's
  /// re-sightings have a mean whitened squared residual above `relinearize_chi2` (a loop closure),
  /// run `incremental_iterations` warm-started Gauss-Newton iterations on the whole graph.
  /// finish() always solves to convergence (the batch optimum).
  int relinearize_every = 10;      ///< [poses]; 0: only at finish()
  int incremental_iterations = 2;  ///< Gauss-Newton iterations of one incremental update
  double relinearize_chi2 = 16.0;  ///< [dimensionless, per 2-D reading]; 0: never early
  /// An incremental update stops relinearizing once a Gauss-Newton step moves no variable by
  /// more than this (max |dx|) [m, rad]: the linearization point has not moved enough to make
  /// the next iteration worth a factorization. 0: always `incremental_iterations` iterations.
  double relinearize_threshold = 0;
  /// The fill-reducing ordering is kept while the structure grows (new variables eliminated
  /// last, IncrementalOrdering) until nnz(L) / nnz(H) exceeds this factor times the one of the
  /// last fresh ordering [dimensionless]; 0: a fresh ordering at every structure change (the
  /// default: on Victoria Park the kept ordering's extra fill costs more than the analyses it
  /// saves, docs/PERFORMANCE.md "Incremental graph backend").
  double reorder_fill_ratio = 0;
  /// Bounded graph for lifelong runs: when the graph holds more poses than this, the oldest
  /// ones leave (their sightings are dropped, their prior composed with the odometry into a prior
  /// on the next pose; a landmark left without sightings keeps its marginal as a prior). 0:
  /// unbounded. docs/GRAPH.md "Bounded graph".
  int max_poses = 0;

  double prior_std_xy = 1e-3;       ///< prior on the start pose (the origin) [m]
  double prior_std_yaw_deg = 1e-2;  ///< [deg]
  /// A step with no odometry: zero increment with this covariance [m], [deg].
  double no_odometry_std_xy = 0.01;
  double no_odometry_std_yaw_deg = 0.5;
  /// Odometry covariances are floored to these standard deviations in every direction (MRPT may
  /// give a singular one) [m], [deg].
  double odometry_min_std_xy = 1e-4;
  double odometry_min_std_yaw_deg = 1e-3;
  /// robotPose() covariance: true = the exact marginal at every query (one factorization of the
  /// whole graph per step when asked every step); false = exact when a factorization at the
  /// current estimate exists (after an update, finish() or any covariance query), otherwise the
  /// last one propagated through the odometry since (EKF prediction; the sightings since are
  /// left out, so it can only be larger than the exact one).
  bool exact_pose_covariance = false;
  /// Readings without landmark ID: nearest neighbour within this Mahalanobis gate (chi2, 2 dof;
  /// 9.21 = 99 %), otherwise a new landmark.
  double association_gate_chi2 = 9.21;
  /// informationGain(): marginal = docs/GRAPH.md's IG (L marginalized out of the "with" term; a
  /// landmark seen once gives 0); conditional = Choudhary et al. Alg. 2 as printed (r given L,
  /// conditionalInformationGain). docs/GRAPH.md "Information gain".
  std::string information_gain = "marginal";

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                          const std::string& section) override;
  void dumpToTextStream(std::ostream& out) const override;
  static std::vector<std::string> keys();

  SolverSettings solverSettings() const;
};

/// Range-bearing sensor noise, read from the same keys as MRPT's EKF
/// (CRangeBearingKFSLAM2D::TOptions), section [RangeBearingKFSLAM].
struct RangeBearingNoise : public mrpt::config::CLoadableOptions {
  static constexpr const char* kSection = "RangeBearingKFSLAM";

  double std_sensor_range = 0.1;    ///< [m]
  double std_sensor_yaw_deg = 0.5;  ///< [deg]

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                          const std::string& section) override;
  void dumpToTextStream(std::ostream& out) const override;
  /// The two keys read here (the rest of [RangeBearingKFSLAM] belongs to the EKF).
  static std::vector<std::string> keys();
};

}  // namespace budget_slam::graph
