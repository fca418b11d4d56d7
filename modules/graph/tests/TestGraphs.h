#pragma once
// Graphs and step sequences for the graph tests and benchmark: seeded synthetic worlds and the
// Victoria Park rawlog of rawlogs/ (read with the dataset module, as the app reads it).
#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <mrpt/config/CConfigFile.h>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/GraphOptions.h"
#include "budget_slam/graph/Solver.h"

namespace budget_slam::graph::testgraphs {

/// A robot walking a seeded random path (1 m steps, turns up to +-0.3 rad) among landmarks
/// scattered over its area; each landmark in range (8 m) is seen with probability `p_see`.
/// Ground truth and noisy readings/odometry; the returned graph starts from a perturbed estimate.
/// Landmark 1000 is seen exactly once.
inline FactorGraph randomGraph(int n_poses, int n_landmarks, unsigned seed, double p_see = 0.35,
                               const Pose2& sensor = Pose2(0.3, 0.1, 0.05)) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<Pose2> truth{Pose2(0, 0, 0)};
  for (int i = 1; i < n_poses; ++i)
    truth.push_back(compose(truth.back(), Pose2(1.0, 0.0, 0.6 * (U(rng) - 0.5))));
  Eigen::Vector2d lo = truth[0].translation(), hi = lo;
  for (const Pose2& p : truth) {
    lo = lo.cwiseMin(p.translation());
    hi = hi.cwiseMax(p.translation());
  }
  lo.array() -= 4;
  hi.array() += 4;
  std::vector<Eigen::Vector2d> lms;
  for (int j = 0; j < n_landmarks; ++j)
    lms.emplace_back(lo.x() + U(rng) * (hi.x() - lo.x()), lo.y() + U(rng) * (hi.y() - lo.y()));

  const Eigen::Matrix3d odo_cov =
      Eigen::Vector3d(0.05 * 0.05, 0.02 * 0.02, 0.01 * 0.01).asDiagonal();
  const Eigen::Matrix2d rb_cov = Eigen::Vector2d(0.1 * 0.1, 0.02 * 0.02).asDiagonal();
  const Eigen::LLT<Eigen::Matrix3d> odo_l(odo_cov);
  FactorGraph g;
  auto perturb = [&](const Pose2& p) {
    return Pose2(p.x + 0.1 * N(rng), p.y + 0.1 * N(rng), p.phi + 0.03 * N(rng));
  };
  g.addFirstPose(0, 0.0, perturb(truth[0]),
                 PriorFactor::make(truth[0], Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal()));
  for (int i = 1; i < n_poses; ++i) {
    Pose2 z = between(truth[i - 1], truth[i]);
    z = Pose2(z.vector() + odo_l.matrixL() * Eigen::Vector3d(N(rng), N(rng), N(rng)));
    g.addPose(i, i, perturb(truth[i]), BetweenFactor::make(z, odo_cov));
  }
  auto observe = [&](int i, int j, LandmarkId id) {
    RangeBearingFactor f = RangeBearingFactor::make(0, 0, sensor, rb_cov);
    const Eigen::Vector2d h = f.predict(truth[i], lms[j]);
    f.range = h.x() + 0.1 * N(rng);
    f.bearing = wrapAngle(h.y() + 0.02 * N(rng));
    if (!g.hasLandmark(id)) g.addLandmark(id, lms[j] + Eigen::Vector2d(0.2 * N(rng), 0.2 * N(rng)));
    g.addObservation(i, id, f);
  };
  for (int i = 0; i < n_poses; ++i)
    for (int j = 0; j < n_landmarks; ++j)
      if ((truth[i].translation() - lms[j]).norm() < 8.0 && U(rng) < p_see) observe(i, j, j);
  lms.emplace_back(truth[n_poses / 2].translation() + Eigen::Vector2d(3, 1));
  observe(n_poses / 2, n_landmarks, 1000);
  return g;
}

/// The same kind of world as a sequence of Steps for the backend: odometry with covariance and
/// range-bearing scans with landmark ids (or none when `with_ids` is false).
struct SyntheticRun {
  std::vector<Step> steps;
  std::vector<Pose2> truth;                ///< pose of each step
  std::vector<Eigen::Vector2d> landmarks;  ///< id = index
};

inline SyntheticRun syntheticRun(int n_steps, int n_landmarks, unsigned seed, bool with_ids = true,
                                 double max_range = 8.0,
                                 const Pose2& sensor = Pose2(0.2, 0.05, 0.1)) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  SyntheticRun run;
  // A loop: circle of radius 10 m, so landmarks are seen again (loop closures).
  const double r = 10.0, dth = 2 * M_PI / 40;
  for (int j = 0; j < n_landmarks; ++j) {
    const double a = 2 * M_PI * j / n_landmarks,
                 rr = r + (j % 2 ? 4.0 : -4.0) * (0.5 + 0.5 * U(rng));
    run.landmarks.emplace_back(rr * std::cos(a), r + rr * std::sin(a));
  }
  Pose2 x(0, 0, 0);
  const Pose2 step_z(2 * r * std::sin(dth / 2), 0, dth);
  const Eigen::Matrix3d odo_cov =
      Eigen::Vector3d(0.02 * 0.02, 0.01 * 0.01, 0.005 * 0.005).asDiagonal();
  for (int k = 0; k < n_steps; ++k) {
    Step s;
    s.index = k;
    s.t = 0.1 * k;
    x = compose(x, step_z);
    run.truth.push_back(x);
    OdometryIncrement o;
    o.mean = Pose2(step_z.x + 0.02 * N(rng), step_z.y + 0.01 * N(rng), step_z.phi + 0.005 * N(rng));
    o.cov = odo_cov;
    s.odometry = o;
    RangeBearingScan scan;
    scan.sensor_pose_on_robot = mrpt::math::TPose3D(sensor.x, sensor.y, 0, sensor.phi, 0, 0);
    const Pose2 sp = compose(x, sensor);
    for (int j = 0; j < n_landmarks; ++j) {
      const Eigen::Vector2d d = run.landmarks[j] - sp.translation();
      if (d.norm() > max_range) continue;
      RangeBearingReading z;
      z.id = with_ids ? j : kNoLandmarkId;
      z.range = d.norm() + 0.05 * N(rng);
      z.yaw = wrapAngle(std::atan2(d.y(), d.x()) - sp.phi + 0.01 * N(rng));
      scan.readings.push_back(z);
    }
    s.scan = scan;
    run.steps.push_back(s);
  }
  return run;
}

/// The first `max_steps` steps of rawlogs/victoria_park.rawlog (made by budget-convert from the
/// iSAM file in data/datasets) and its sensor noise from rawlogs/victoria_park.ini, read as
/// the app reads them. Empty when the rawlog is absent.
inline std::vector<Step> victoriaParkSteps(std::size_t max_steps, RangeBearingNoise* noise) {
  const std::string rawlog = std::string(BUDGET_SLAM_SOURCE_DIR) + "/rawlogs/victoria_park.rawlog";
  const std::string ini = std::string(BUDGET_SLAM_SOURCE_DIR) + "/rawlogs/victoria_park.ini";
  std::vector<Step> steps;
  if (!std::ifstream(rawlog).good() || !std::ifstream(ini).good()) return steps;
  mrpt::config::CConfigFile cfg(ini);
  noise->loadFromConfigFile(cfg, RangeBearingNoise::kSection);
  dataset::RawlogReader reader(rawlog);
  while (steps.size() < max_steps) {
    std::optional<Step> s = reader.next();
    if (!s) break;
    steps.push_back(std::move(*s));
  }
  return steps;
}

/// Dense Gauss-Newton to convergence (|dx| < 1e-14 or 200 iterations): the batch reference.
inline Eigen::VectorXd denseBatchSolve(FactorGraph g) {
  for (int it = 0; it < 200; ++it) {
    Eigen::SparseMatrix<double> Hs;
    Eigen::VectorXd grad;
    g.linearize(&Hs, &grad);
    const Eigen::MatrixXd H = Eigen::MatrixXd(Hs).selfadjointView<Eigen::Lower>();
    const Eigen::VectorXd dx = -H.ldlt().solve(grad);
    g.retract(dx);
    if (dx.lpNorm<Eigen::Infinity>() < 1e-14) break;
  }
  return g.values();
}

/// randomGraph() solved to its batch optimum, with `chol` holding H factorized there.
inline FactorGraph solvedRandomGraph(int n_poses, int n_landmarks, unsigned seed,
                                     SparseCholesky* chol) {
  FactorGraph g = randomGraph(n_poses, n_landmarks, seed);
  optimize(g, SolverSettings{}, chol);
  factorizeAtEstimate(g, chol);
  return g;
}

/// Range-bearing sensor noise for a GraphBackend: 1-sigma range [m] and bearing [deg].
inline RangeBearingNoise sensorNoise(double std_range_m, double std_yaw_deg) {
  RangeBearingNoise n;
  n.std_sensor_range = std_range_m;
  n.std_sensor_yaw_deg = std_yaw_deg;
  return n;
}

/// Full symmetric dense H at the graph's estimate.
inline Eigen::MatrixXd denseInformation(const FactorGraph& g) {
  Eigen::SparseMatrix<double> Hs;
  Eigen::VectorXd grad;
  g.linearize(&Hs, &grad);
  return Eigen::MatrixXd(Eigen::MatrixXd(Hs).selfadjointView<Eigen::Lower>());
}

}  // namespace budget_slam::graph::testgraphs
