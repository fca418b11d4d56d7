#pragma once
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/graph/Solver.h"

namespace budget_slam::graph {

/// [GraphSLAM]: the landmark graph backend (docs/GRAPH.md), MRPT's CLoadableOptions pattern with
/// every key defined once in table() (loading, the dump and the unknown-key check follow from it).
/// A bad value is a ConfigError naming the section, key and value.
struct GraphSlamOptions : public TabledOptions<GraphSlamOptions> {
  static constexpr const char* kSection = "GraphSLAM";

  /// informationGain(): marginal = docs/GRAPH.md's IG (L marginalized out of the "with" term; a
  /// landmark seen once gives 0); conditional = Choudhary et al. Alg. 2 as printed (r given L,
  /// conditionalInformationGain). docs/GRAPH.md "Information gain".
  enum class InformationGain { Marginal, Conditional };

  /// The full solves (finish(), optimize()), keys `solver` (gauss-newton | levenberg-marquardt:
  /// SolverSettings::method), `max_iterations` (default 100 here), `step_tolerance` [m, rad],
  /// `relative_chi2_tolerance`, `lm_initial_lambda`, `lm_lambda_factor`. The incremental updates
  /// start from these too (Gauss-Newton, incremental_iterations iterations).
  SolverSettings solver = SolverSettings{SolverSettings::Method::GaussNewton, 100};

  /// Incremental schedule: after every `relinearize_every` new poses, or as soon as a step's
  /// re-sightings have a mean whitened squared residual above `relinearize_chi2` (a loop closure),
  /// run `incremental_iterations` warm-started Gauss-Newton iterations on the whole graph.
  /// finish() always solves to convergence (the batch optimum).
  int relinearize_every = 10;      ///< [poses]; 0: only at finish()
  int incremental_iterations = 2;  ///< Gauss-Newton iterations of one incremental update
  double relinearize_chi2 = 16.0;  ///< [dimensionless, per 2-D reading]; 0: never early
  /// Per-variable relinearization (iSAM2's threshold): in an incremental update a variable's
  /// factors are relinearized only when its estimate has moved by more than this from their
  /// linearization point (max |dx| over its parameters) [m, rad]; the estimate itself takes
  /// every Gauss-Newton step (the minimizer of the held linear model). 0: every variable that
  /// moved (full Gauss-Newton). finish() relinearizes everything that moved.
  /// docs/GRAPH.md "Held factor".
  double relinearize_threshold = 0.1;
  /// Partial back-substitution (iSAM2's wildfire threshold): after a change, an incremental
  /// update solves again the rows of the solution the change re-eliminated, and a row above them
  /// only when a row of its column of L moved by more than this [m, rad]. 0: every change
  /// spreads (the solution of a whole solve, to rounding). finish() uses 0.
  /// docs/GRAPH.md "Partial back-substitution".
  double wildfire_threshold = 0.001;
  /// The held factor keeps its fill-reducing ordering (new variables eliminated last) until
  /// nnz(L) per row exceeds this factor times its value right after the last fresh ordering
  /// [dimensionless]; then it is rebuilt with a fresh one. At most 1: a fresh ordering and a
  /// full refactorization at every change (no in-place updates).
  double reorder_fill_ratio = 1.5;
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
  /// informationGain(): marginal | conditional (InformationGain).
  InformationGain information_gain = InformationGain::Marginal;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<GraphSlamOptions>& table();
  /// The ini names of `solver` and `information_gain`, in the order errors list them.
  static const EnumNames<SolverSettings::Method>& solverNames();
  static const EnumNames<InformationGain>& informationGainNames();
};

/// Range-bearing sensor noise, read from the same keys as MRPT's EKF
/// (CRangeBearingKFSLAM2D::TOptions), section [RangeBearingKFSLAM]; the same rule as the EKF's
/// (ekf::checkMrptKfSlamOptions: IniSection::readStd). keys() lists only these two: the rest of
/// [RangeBearingKFSLAM] belongs to the EKF.
struct RangeBearingNoise : public TabledOptions<RangeBearingNoise> {
  static constexpr const char* kSection = "RangeBearingKFSLAM";

  double std_sensor_range = 0.1;    ///< [m]
  double std_sensor_yaw_deg = 0.5;  ///< [deg]

  static const OptionTable<RangeBearingNoise>& table();
};

}  // namespace budget_slam::graph
