#include "budget_slam/graph/GraphBackend.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/graph/InformationGain.h"
#include "budget_slam/graph/Marginals.h"

namespace budget_slam::graph {

namespace {
constexpr double kDeg = M_PI / 180.0;

Pose2 toPose2(const mrpt::math::TPose2D& p) { return Pose2(p.x, p.y, p.phi); }

/// Floors a covariance to the standard deviations `min_std` in every direction: eigenvalues of
/// D^-1 C D^-1 (D = diag(min_std)) are raised to at least 1. MRPT odometry may be singular.
Eigen::Matrix3d floorCovariance(const Eigen::Matrix3d& C, const Eigen::Vector3d& min_std) {
  const Eigen::Matrix3d Dinv = min_std.cwiseInverse().asDiagonal();
  Eigen::Matrix3d S = Dinv * (0.5 * (C + C.transpose())) * Dinv;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S);
  const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(1.0);
  S = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
  const Eigen::Matrix3d D = min_std.asDiagonal();
  return D * S * D;
}
}  // namespace

GraphBackend::GraphBackend(const mrpt::config::CConfigFileBase& ini) {
  options_.loadFromConfigFile(ini, GraphSlamOptions::kSection);
  noise_.loadFromConfigFile(ini, RangeBearingNoise::kSection);
  solver_ordering_ = IncrementalOrdering(options_.reorder_fill_ratio);
  query_ordering_ = IncrementalOrdering(options_.reorder_fill_ratio);
}

GraphBackend::GraphBackend(const GraphSlamOptions& options, const RangeBearingNoise& noise)
    : options_(options),
      noise_(noise),
      solver_ordering_(options.reorder_fill_ratio),
      query_ordering_(options.reorder_fill_ratio) {}

GraphBackend::GraphBackend(const GraphBackend& o)
    : options_(o.options_),
      noise_(o.noise_),
      graph_(o.graph_),
      tracks_(o.tracks_),
      next_fresh_id_(o.next_fresh_id_),
      poses_since_update_(o.poses_since_update_),
      updates_(o.updates_),
      poses_dropped_(o.poses_dropped_),
      solver_ordering_(o.options_.reorder_fill_ratio),
      estimate_version_(o.estimate_version_),
      exact_version_(o.exact_version_),
      pose_cov_(o.pose_cov_),
      landmark_cov_(o.landmark_cov_),
      landmark_cov_version_(o.landmark_cov_version_),
      query_ordering_(o.options_.reorder_fill_ratio) {}

std::unique_ptr<Backend> GraphBackend::clone() const {
  return std::unique_ptr<Backend>(new GraphBackend(*this));
}

BetweenFactor GraphBackend::odometryFactor(const Step& step) const {
  if (!step.odometry) {
    const double sxy = options_.no_odometry_std_xy, syaw = options_.no_odometry_std_yaw_deg * kDeg;
    return BetweenFactor::make(Pose2::Zero(),
                               Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal());
  }
  if (!step.odometry->cov.allFinite())
    throw std::invalid_argument("step " + std::to_string(step.index) +
                                ": odometry covariance is not finite");
  const Eigen::Vector3d min_std(options_.odometry_min_std_xy, options_.odometry_min_std_xy,
                                options_.odometry_min_std_yaw_deg * kDeg);
  return BetweenFactor::make(toPose2(step.odometry->mean),
                             floorCovariance(step.odometry->cov, min_std));
}

std::vector<LandmarkId> GraphBackend::associate(const RangeBearingScan& scan, StepIndex pose,
                                                const Pose2& sensor) const {
  std::vector<LandmarkId> ids(scan.readings.size(), kNoLandmarkId);
  bool any = false;
  for (std::size_t r = 0; r < scan.readings.size(); ++r) {
    ids[r] = scan.readings[r].id;
    any |= ids[r] == kNoLandmarkId;
  }
  if (!any || graph_.landmarks().empty()) return ids;
  // Joint marginal of the new pose and every landmark (one factorization; only rawlogs without
  // landmark IDs pay for it): the innovation covariance S = R + J Sigma J^T, J = [J_x J_l],
  // includes the pose uncertainty and its correlation with each landmark.
  std::vector<VariableKey> vars{VariableKey::pose(pose)};
  for (const auto& [id, l] : graph_.landmarks()) vars.push_back(VariableKey::landmark(id));
  const Eigen::MatrixXd Sigma = jointMarginal(graph_, factorization(), vars);
  const Pose2& x = graph_.pose(pose).x;
  const Eigen::Matrix2d R = sensorCovariance();
  struct Pair {
    double d2;
    std::size_t r;
    LandmarkId id;
  };
  std::vector<Pair> pairs;
  for (std::size_t r = 0; r < scan.readings.size(); ++r) {
    if (ids[r] != kNoLandmarkId) continue;
    const RangeBearingFactor f =
        RangeBearingFactor::make(scan.readings[r].range, scan.readings[r].yaw, sensor, R);
    int k = 3;
    for (const auto& [id, l] : graph_.landmarks()) {
      Eigen::Matrix<double, 2, 3> Jx;
      Eigen::Matrix2d Jl;
      const Eigen::Vector2d e = f.error(x, l.x, &Jx, &Jl);
      Eigen::Matrix<double, 2, 5> J;
      J << Jx, Jl;
      Eigen::Matrix<double, 5, 5> P;
      P << Sigma.topLeftCorner<3, 3>(), Sigma.block<3, 2>(0, k), Sigma.block<2, 3>(k, 0),
          Sigma.block<2, 2>(k, k);
      const Eigen::Matrix2d S = R + J * P * J.transpose();
      const double d2 = e.dot(S.ldlt().solve(e));
      if (d2 < options_.association_gate_chi2) pairs.push_back({d2, r, id});
      k += 2;
    }
  }
  // Greedy nearest neighbour: closest pairs first, one landmark per reading and per scan.
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d2 < b.d2; });
  std::vector<LandmarkId> used;
  for (const Pair& p : pairs) {
    if (ids[p.r] != kNoLandmarkId || std::count(used.begin(), used.end(), p.id)) continue;
    ids[p.r] = p.id;
    used.push_back(p.id);
  }
  return ids;  // still kNoLandmarkId: a new landmark (fresh id given by process())
}

Eigen::Matrix2d GraphBackend::sensorCovariance() const {
  const double sr = noise_.std_sensor_range, sy = noise_.std_sensor_yaw_deg * kDeg;
  return Eigen::Vector2d(sr * sr, sy * sy).asDiagonal();
}

void GraphBackend::process(const Step& step) {
  last_ids_.clear();
  const BetweenFactor odo = odometryFactor(step);
  if (graph_.poses().empty()) {
    // Step 0's action moves the robot from the start pose (the origin, as MRPT's filter) to pose 0.
    // The start pose sees nothing, so it is marginalized at once: prior on pose 0 = origin (+) odo,
    // covariance J_a C_prior J_a^T + J_b C_odo J_b^T (composeBetween).
    const double sxy = options_.prior_std_xy, syaw = options_.prior_std_yaw_deg * kDeg;
    const BetweenFactor start = BetweenFactor::make(
        Pose2::Zero(), Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal());
    const BetweenFactor first = composeBetween(start, odo);
    graph_.addFirstPose(step.index, step.t, first.z, PriorFactor::make(first.z, first.cov));
    pose_cov_ = first.cov;
  } else {
    const Pose2& last = graph_.poses().rbegin()->second.x;
    Eigen::Matrix3d Ja, Jb;
    graph_.addPose(step.index, step.t, compose(last, odo.z, &Ja, &Jb), odo);
    if (pose_cov_) *pose_cov_ = Ja * *pose_cov_ * Ja.transpose() + Jb * odo.cov * Jb.transpose();
  }
  ++poses_since_update_;
  touch();

  double resight_chi2 = 0;
  std::size_t resights = 0;
  if (step.scan) {
    const RangeBearingScan& scan = *step.scan;
    const Pose2 sensor(scan.sensor_pose_on_robot.x, scan.sensor_pose_on_robot.y,
                       scan.sensor_pose_on_robot.yaw);
    const Pose2 x = graph_.poses().rbegin()->second.x;
    const Eigen::Matrix2d R = sensorCovariance();
    for (std::size_t r = 0; r < scan.readings.size(); ++r) {
      const RangeBearingReading& z = scan.readings[r];
      if (!std::isfinite(z.range) || !std::isfinite(z.yaw) || z.range <= 0)
        throw std::invalid_argument("step " + std::to_string(step.index) + ": reading " +
                                    std::to_string(r) + " has a bad range or bearing");
    }
    const bool needs_association =
        std::any_of(scan.readings.begin(), scan.readings.end(),
                    [](const RangeBearingReading& z) { return z.id == kNoLandmarkId; });
    if (needs_association && !graph_.landmarks().empty() && poses_since_update_ > 0) {
      // The gate assumes the estimate is the MAP of the data so far (its covariance is only
      // meaningful there): dead-reckoned poses since the last update are not. Update first.
      incrementalUpdate();
    }
    const std::vector<LandmarkId> ids = associate(scan, step.index, sensor);
    for (LandmarkId id : ids)
      if (id != kNoLandmarkId) next_fresh_id_ = std::max(next_fresh_id_, id + 1);
    last_ids_.assign(scan.readings.size(), kNoLandmarkId);
    for (std::size_t r = 0; r < scan.readings.size(); ++r) {
      const RangeBearingReading& z = scan.readings[r];
      LandmarkId id = ids[r];
      if (id == kNoLandmarkId) id = next_fresh_id_++;
      last_ids_[r] = id;
      const RangeBearingFactor f = RangeBearingFactor::make(z.range, z.yaw, sensor, R);
      if (!graph_.hasLandmark(id)) {
        graph_.addLandmark(id, f.landmarkFrom(x));  // re-seen after removal: back as new
        tracks_[id] = Track{0, Eigen::Vector2d::Zero(), step.index, step.index};
      } else {
        resight_chi2 += (f.sqrt_info * f.error(x, graph_.landmark(id).x)).squaredNorm();
        ++resights;
      }
      graph_.addObservation(step.index, id, f);
      Track& t = tracks_[id];
      ++t.n;
      t.obs_mean += (x.head<2>() - t.obs_mean) / static_cast<double>(t.n);
      t.last_step = step.index;
    }
  }

  // Incremental schedule (docs/GRAPH.md): a few warm-started Gauss-Newton iterations every
  // `relinearize_every` poses, or at once when the re-sightings disagree with the estimate.
  const bool periodic =
      options_.relinearize_every > 0 && poses_since_update_ >= options_.relinearize_every;
  const bool surprised = options_.relinearize_chi2 > 0 && resights > 0 &&
                         resight_chi2 / static_cast<double>(resights) > options_.relinearize_chi2;
  if (periodic || surprised) incrementalUpdate();
  boundPoses();
}

void GraphBackend::boundPoses() {
  const std::size_t limit = static_cast<std::size_t>(std::max(options_.max_poses, 0));
  const std::size_t n = graph_.poses().size();
  if (limit == 0 || n <= limit) return;
  // Drop a tenth of the window at once (at least the excess): landmarks left without sightings
  // need one factorization for their marginals, shared by the whole batch.
  const std::size_t count = std::min(n - 1, std::max(n - limit, limit / 10));
  auto first_kept = std::next(graph_.poses().begin(), static_cast<std::ptrdiff_t>(count));
  const StepIndex first_step = first_kept->first;
  // Landmarks all of whose sightings leave: their marginal at the current estimate becomes a
  // prior (in place of any earlier one, which the marginal includes).
  std::vector<VariableKey> orphans;
  for (const auto& [id, l] : graph_.landmarks()) {
    const bool keeps = std::any_of(l.obs.begin(), l.obs.end(),
                                   [&](const Observation& o) { return o.pose >= first_step; });
    if (!keeps && !l.obs.empty()) orphans.push_back(VariableKey::landmark(id));
  }
  std::vector<Eigen::MatrixXd> cov;
  if (!orphans.empty()) cov = marginals(graph_, factorization(), orphans);
  // The new first pose's prior: the dropped poses' prior and odometry composed up to it (exact
  // marginalization once their sightings are gone: a chain), linearized at the current estimate,
  // with the current estimate as its mean (where the dropped sightings put it stays; their
  // information does not).
  const PriorFactor& p0 = graph_.prior();
  BetweenFactor acc = BetweenFactor::make(graph_.poses().begin()->second.x, p0.cov);
  for (auto it = std::next(graph_.poses().begin());; ++it) {
    const BetweenFactor hop =
        BetweenFactor::make(between(acc.z, it->second.x), it->second.odo->cov);
    acc = composeBetween(acc, hop);
    if (it == first_kept) break;
  }
  for (std::size_t k = 0; k < orphans.size(); ++k) {
    const LandmarkId id = orphans[k].id;
    graph_.setLandmarkPrior(id, LandmarkPrior::make(graph_.landmark(id).x, cov[k]));
  }
  graph_.dropFirstPoses(count, PriorFactor::make(first_kept->second.x, acc.cov));
  poses_dropped_ += count;
  touch();
}

void GraphBackend::incrementalUpdate() {
  SolverSettings s = options_.solverSettings();
  s.method = SolverSettings::Method::GaussNewton;
  s.max_iterations = options_.incremental_iterations;
  s.step_tolerance = std::max(s.step_tolerance, options_.relinearize_threshold);
  graph::optimize(graph_, s, &solver_chol_, &solver_ordering_);
  poses_since_update_ = 0;
  ++updates_;
  touch();
  // The solver's last factorization is of the current structure, linearized one step before the
  // final estimate: the latest pose's marginal from it is exact up to that last step.
  pose_cov_ =
      jointMarginal(graph_, solver_chol_, {VariableKey::pose(graph_.poses().rbegin()->first)});
}

const SparseCholesky& GraphBackend::factorization() const {
  if (query_version_ != estimate_version_) {
    factorizeAtEstimate(graph_, &query_chol_, &query_ordering_);
    query_version_ = estimate_version_;
    exact_version_ = estimate_version_;
  }
  return query_chol_;
}

std::vector<LandmarkView> GraphBackend::landmarks() const {
  std::vector<LandmarkView> out;
  out.reserve(graph_.landmarks().size());
  if (graph_.landmarks().empty()) return out;
  if (landmark_cov_version_ != estimate_version_) {
    std::vector<VariableKey> vars;
    for (const auto& [id, l] : graph_.landmarks()) vars.push_back(VariableKey::landmark(id));
    const std::vector<Eigen::MatrixXd> m = marginals(graph_, factorization(), vars);
    landmark_cov_.clear();
    for (std::size_t k = 0; k < vars.size(); ++k) landmark_cov_[vars[k].id] = m[k];
    landmark_cov_version_ = estimate_version_;
  }
  for (const auto& [id, l] : graph_.landmarks()) {
    const Track& t = tracks_.at(id);
    LandmarkView v;
    v.id = id;
    v.mean = l.x;
    v.cov = landmark_cov_.at(id);
    v.n_obs = t.n;
    v.obs_mean = t.obs_mean;
    v.first_step = t.first_step;
    v.last_step = t.last_step;
    out.push_back(v);
  }
  return out;
}

std::vector<LandmarkId> GraphBackend::observedAt(StepIndex step) const {
  std::vector<LandmarkId> out;
  for (const auto& [id, t] : tracks_)  // a std::map: already sorted by id
    if (t.last_step == step && t.n > 0) out.push_back(id);
  return out;
}

PoseEstimate GraphBackend::robotPose() const {
  PoseEstimate p;
  if (graph_.poses().empty()) return p;
  const auto& [step, node] = *graph_.poses().rbegin();
  p.mean = mrpt::math::TPose2D(node.x.x(), node.x.y(), node.x.z());
  if (options_.exact_pose_covariance || !pose_cov_ || exact_version_ == estimate_version_) {
    pose_cov_ = jointMarginal(graph_, factorization(), {VariableKey::pose(step)});
  }
  p.cov = *pose_cov_;
  return p;
}

std::vector<TrajectoryPoint> GraphBackend::trajectory() const {
  std::vector<TrajectoryPoint> out;
  out.reserve(graph_.poses().size());
  for (const auto& [step, node] : graph_.poses())
    out.push_back({step, node.t, mrpt::math::TPose2D(node.x.x(), node.x.y(), node.x.z())});
  return out;
}

void GraphBackend::removeLandmark(LandmarkId id) {
  if (!graph_.hasLandmark(id))
    throw std::out_of_range("graph backend: no landmark " + std::to_string(id));
  graph_.removeLandmark(id);
  tracks_.erase(id);
  landmark_cov_.erase(id);
  pose_cov_.reset();  // the pose lost information: recompute exactly at the next query
  touch();
}

std::vector<double> GraphBackend::informationGain(const std::vector<LandmarkId>& ids) const {
  for (LandmarkId id : ids)
    if (!graph_.hasLandmark(id))
      throw std::out_of_range("graph backend: no landmark " + std::to_string(id));
  if (ids.empty()) return {};
  if (options_.information_gain == "conditional")
    return graph::conditionalInformationGain(graph_, factorization(), ids);
  return graph::informationGain(graph_, factorization(), ids);
}

Eigen::Matrix2d GraphBackend::landmarkCovariance(LandmarkId id) const {
  if (!graph_.hasLandmark(id))
    throw std::out_of_range("graph backend: no landmark " + std::to_string(id));
  if (landmark_cov_version_ == estimate_version_) return landmark_cov_.at(id);
  return jointMarginal(graph_, factorization(), {VariableKey::landmark(id)});
}

Eigen::MatrixXd GraphBackend::jointCovariance(const std::vector<VariableKey>& vars) const {
  if (vars.empty()) return Eigen::MatrixXd(0, 0);
  for (const VariableKey& v : vars) graph_.column(v);  // throws std::out_of_range if unknown
  return jointMarginal(graph_, factorization(), vars);
}

std::size_t GraphBackend::marginalizePosesWithoutLandmarks(std::size_t keep_last) {
  // Choudhary et al. Alg. 3 lines 15-16: poses that see no kept landmark leave, except the first
  // and the last `keep_last` (and always the latest: the robot's current pose).
  const std::size_t n = graph_.poses().size();
  const std::size_t keep = std::max<std::size_t>(keep_last, 1);
  if (n <= keep + 1) return 0;
  std::vector<StepIndex> victims;
  std::size_t k = 0;
  for (const auto& [step, node] : graph_.poses()) {
    if (k > 0 && k + keep < n && node.n_obs == 0) victims.push_back(step);
    ++k;
  }
  for (StepIndex s : victims) graph_.marginalizePose(s);
  if (!victims.empty()) {
    pose_cov_.reset();
    touch();
  }
  return victims.size();
}

SolveReport GraphBackend::optimize() {
  SolverSettings settings = options_.solverSettings();
  settings.stop_on_request = true;  // a full solve of a long run takes seconds
  SolveReport r;
  try {
    r = graph::optimize(graph_, settings, &solver_chol_, &solver_ordering_);
  } catch (const Interrupted&) {
    // The estimate moved to the last accepted iterate: the caches must follow it.
    pose_cov_.reset();
    touch();
    throw;
  }
  poses_since_update_ = 0;
  pose_cov_.reset();
  touch();
  return r;
}

void GraphBackend::finish() { optimize(); }

}  // namespace budget_slam::graph
