#include "budget_slam/graph/GraphBackend.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/graph/GraphSession.h"
#include "budget_slam/graph/InformationGain.h"
#include "budget_slam/graph/Marginals.h"
#include "budget_slam/graph/NearestNeighbourAssociation.h"

namespace budget_slam::graph {

namespace {
constexpr double kDeg = M_PI / 180.0;
/// Poses a saved graph may hold without `max_poses` (a bound on what a session file can make the
/// reader build; Victoria Park's whole run is 6968).
constexpr std::size_t kMaxSavedPoses = std::size_t{1} << 20;
/// How far the saved robot may stand from the saved chain's last pose [m], [rad]: both are written
/// from the same doubles, so only rounding in a hand-made file.
constexpr double kSameRobotM = 1e-9, kSameRobotRad = 1e-9;

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

/// Options of type T read from their own section of `ini`.
template <typename T>
T loaded(const mrpt::config::CConfigFileBase& ini) {
  T t;
  t.loadFromConfigFile(ini, T::kSection);
  return t;
}
}  // namespace

GraphBackend::GraphBackend(const mrpt::config::CConfigFileBase& ini)
    : GraphBackend(loaded<GraphSlamOptions>(ini), loaded<RangeBearingNoise>(ini)) {}

GraphBackend::GraphBackend(const GraphSlamOptions& options, const RangeBearingNoise& noise)
    : options_(options), noise_(noise), factorization_(options.reorder_fill_ratio) {}

GraphBackend::GraphBackend(const GraphBackend& o)
    : options_(o.options_),
      noise_(o.noise_),
      graph_(o.graph_),
      tracks_(o.tracks_),
      next_fresh_id_(o.next_fresh_id_),
      poses_since_update_(o.poses_since_update_),
      updates_(o.updates_),
      poses_dropped_(o.poses_dropped_),
      factorization_(o.factorization_),
      pose_cov_(o.pose_cov_) {
  factorization_.adopt(graph_);
}

std::unique_ptr<Backend> GraphBackend::clone() const {
  return std::unique_ptr<Backend>(new GraphBackend(*this));
}

BetweenFactor GraphBackend::odometryFactor(const Step& step) const {
  if (!step.odometry) {
    const double sxy = options_.no_odometry_std_xy, syaw = options_.no_odometry_std_yaw_deg * kDeg;
    return BetweenFactor::make(Pose2(),
                               Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal());
  }
  const Eigen::Vector3d min_std(options_.odometry_min_std_xy, options_.odometry_min_std_xy,
                                options_.odometry_min_std_yaw_deg * kDeg);
  // Finite but huge entries overflow once scaled by the floor: the same bad input.
  const Eigen::Matrix3d cov = step.odometry->cov.allFinite()
                                  ? floorCovariance(step.odometry->cov, min_std)
                                  : step.odometry->cov;
  if (!cov.allFinite())
    throw InputError("step " + std::to_string(step.index) +
                     ": the odometry covariance is not finite (the graph backend needs one)");
  return BetweenFactor::make(step.odometry->mean, cov);
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
    // A resumed session starts from the saved (or woken-up) pose and its marginal instead.
    const double sxy = options_.prior_std_xy, syaw = options_.prior_std_yaw_deg * kDeg;
    const BetweenFactor start =
        start_ ? BetweenFactor::make(start_->mean, start_->cov)
               : BetweenFactor::make(
                     Pose2(), Eigen::Vector3d(sxy * sxy, sxy * sxy, syaw * syaw).asDiagonal());
    const BetweenFactor first = composeBetween(start, odo);
    graph_.addFirstPose(step.index, step.t, first.z, PriorFactor::make(first.z, first.cov));
    pose_cov_ = first.cov;
  } else {
    const Pose2 last(graph_.poses().rbegin()->second.x);
    Eigen::Matrix3d Ja, Jb;
    graph_.addPose(step.index, step.t, compose(last, odo.z, &Ja, &Jb), odo);
    if (pose_cov_) *pose_cov_ = Ja * *pose_cov_ * Ja.transpose() + Jb * odo.cov * Jb.transpose();
  }
  ++poses_since_update_;

  double resight_chi2 = 0;
  std::size_t resights = 0;
  if (step.scan) {
    const RangeBearingScan& scan = *step.scan;
    const Pose2 sensor(scan.sensor_pose_on_robot.x, scan.sensor_pose_on_robot.y,
                       scan.sensor_pose_on_robot.yaw);
    const Pose2 x(graph_.poses().rbegin()->second.x);
    const Eigen::Matrix2d R = sensorCovariance();
    for (std::size_t r = 0; r < scan.readings.size(); ++r) {
      const RangeBearingReading& z = scan.readings[r];
      // The rawlog reader admits a zero range; a range-bearing factor cannot use it (its
      // Jacobian divides by the range).
      const std::string at =
          "step " + std::to_string(step.index) + ": reading " + std::to_string(r);
      if (!std::isfinite(z.range) || z.range <= 0)
        throw InputError(at + " has range " + std::to_string(z.range) +
                         " m; the graph backend needs a finite range above 0");
      if (!std::isfinite(z.yaw)) throw InputError(at + " has a non-finite bearing");
    }
    const bool needs_association =
        std::any_of(scan.readings.begin(), scan.readings.end(),
                    [](const RangeBearingReading& z) { return z.id == kNoLandmarkId; });
    if (needs_association && !graph_.landmarks().empty() && poses_since_update_ > 0) {
      // The gate assumes the estimate is the MAP of the data so far (its covariance is only
      // meaningful there): dead-reckoned poses since the last update are not. Update first.
      incrementalUpdate();
    }
    const std::vector<LandmarkId> ids =
        NearestNeighbourAssociation(options_.association_gate_chi2, R)
            .associate(scan, step.index, sensor, graph_, factorization_);
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
        // Re-seen after removal: back as new (removeLandmark erased its track too).
        graph_.addLandmark(id, f.landmarkFrom(x));
      } else {
        resight_chi2 += (f.sqrt_info * f.error(x, graph_.landmark(id).x)).squaredNorm();
        ++resights;
      }
      graph_.addObservation(step.index, id, f);
      tracks_.addSighting(id, x.translation(), step.index);
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
  if (!orphans.empty()) cov = factorization_.marginals(graph_, orphans);
  // The new first pose's prior: the dropped poses' prior and odometry composed up to it (exact
  // marginalization once their sightings are gone: a chain), linearized at the current estimate,
  // with the current estimate as its mean (where the dropped sightings put it stays; their
  // information does not).
  const PriorFactor& p0 = graph_.prior();
  BetweenFactor acc = BetweenFactor::make(Pose2(graph_.poses().begin()->second.x), p0.cov);
  for (auto it = std::next(graph_.poses().begin());; ++it) {
    const BetweenFactor hop =
        BetweenFactor::make(between(acc.z, Pose2(it->second.x)), it->second.odo->cov);
    acc = composeBetween(acc, hop);
    if (it == first_kept) break;
  }
  for (std::size_t k = 0; k < orphans.size(); ++k) {
    const LandmarkId id = orphans[k].id;
    graph_.setLandmarkPrior(id, LandmarkPrior::make(graph_.landmark(id).x, cov[k]));
  }
  graph_.dropFirstPoses(count, PriorFactor::make(Pose2(first_kept->second.x), acc.cov));
  poses_dropped_ += count;
}

void GraphBackend::incrementalUpdate() {
  IncrementalStep s;
  s.max_iterations = options_.incremental_iterations;
  s.relinearize_threshold = options_.relinearize_threshold;
  s.wildfire_threshold = options_.wildfire_threshold;
  s.step_tolerance = options_.solver.step_tolerance;
  s.relative_chi2_tolerance = options_.solver.relative_chi2_tolerance;
  factorization_.held().iterate(graph_, s);
  poses_since_update_ = 0;
  ++updates_;
  // The held factor is of the final estimate: the latest pose's marginal from it is exact.
  pose_cov_ = factorization_.jointMarginal(
      graph_, {VariableKey::pose(graph_.poses().rbegin()->first)}, /*at_estimate=*/false);
}

std::vector<LandmarkView> GraphBackend::landmarks() const {
  std::vector<LandmarkView> out;
  out.reserve(graph_.landmarks().size());
  if (graph_.landmarks().empty()) return out;
  const std::map<LandmarkId, Eigen::Matrix2d>& cov = factorization_.landmarkMarginals(graph_);
  for (const auto& [id, l] : graph_.landmarks()) {
    LandmarkView v;
    v.id = id;
    v.mean = l.x;
    v.cov = cov.at(id);
    tracks_.at(id).describe(&v);
    out.push_back(v);
  }
  return out;
}

std::vector<LandmarkId> GraphBackend::observedAt(StepIndex step) const {
  return tracks_.observedAt(step);
}

PoseEstimate GraphBackend::robotPose() const {
  // Before the first step of a resumed session: the robot where the last one stopped, or where
  // the wake-up found it (what the first step's odometry starts from).
  if (graph_.poses().empty()) return start_ ? *start_ : PoseEstimate{};
  PoseEstimate p;
  const auto& [step, node] = *graph_.poses().rbegin();
  p.mean = Pose2(node.x);
  if (options_.exact_pose_covariance || !pose_cov_ || factorization_.isCurrent(graph_)) {
    pose_cov_ = factorization_.jointMarginal(graph_, {VariableKey::pose(step)},
                                             options_.exact_pose_covariance);
  }
  p.cov = *pose_cov_;
  return p;
}

std::vector<TrajectoryPoint> GraphBackend::trajectory() const {
  std::vector<TrajectoryPoint> out;
  out.reserve(graph_.poses().size());
  for (const auto& [step, node] : graph_.poses()) out.push_back({step, node.t, Pose2(node.x)});
  return out;
}

void GraphBackend::removeLandmark(LandmarkId id) {
  if (!graph_.hasLandmark(id))
    throw std::out_of_range("graph backend: no landmark " + std::to_string(id));
  graph_.removeLandmark(id);
  tracks_.erase(id);
  pose_cov_.reset();  // the pose lost information: recompute exactly at the next query
}

std::vector<double> GraphBackend::informationGain(const std::vector<LandmarkId>& ids) const {
  for (LandmarkId id : ids)
    if (!graph_.hasLandmark(id))
      throw std::out_of_range("graph backend: no landmark " + std::to_string(id));
  if (ids.empty()) return {};
  // The held factor, relinearized where the estimate has left it: H at the estimate.
  const SparseCholesky& chol = factorization_.factor(graph_, /*at_estimate=*/true);
  if (options_.information_gain == GraphSlamOptions::InformationGain::Conditional)
    return graph::conditionalInformationGain(graph_, chol, ids);
  return graph::informationGain(graph_, chol, ids);
}

Eigen::Matrix2d GraphBackend::landmarkCovariance(LandmarkId id) const {
  if (!graph_.hasLandmark(id))
    throw std::out_of_range("graph backend: no landmark " + std::to_string(id));
  return factorization_.landmarkMarginal(graph_, id);
}

Eigen::MatrixXd GraphBackend::jointCovariance(const std::vector<VariableKey>& vars) const {
  if (vars.empty()) return Eigen::MatrixXd(0, 0);
  for (const VariableKey& v : vars) graph_.column(v);  // throws std::out_of_range if unknown
  return factorization_.jointMarginal(graph_, vars);
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
  if (!victims.empty()) pose_cov_.reset();
  return victims.size();
}

SolveReport GraphBackend::optimize() {
  SolverSettings settings = options_.solver;
  settings.stop_on_request = true;  // a full solve of a long run takes seconds
  SolveReport r;
  try {
    if (settings.method == SolverSettings::Method::LevenbergMarquardt) {
      // The damped system is not H: batch factorizations (the held factor follows the new
      // estimate at its next use).
      SparseCholesky chol;
      r = graph::optimize(graph_, settings, &chol);
    } else {
      // Gauss-Newton on the held factor, every variable that moves taking its step.
      IncrementalStep s;
      s.max_iterations = settings.max_iterations;
      s.relinearize_threshold = 0;
      s.step_tolerance = settings.step_tolerance;
      s.relative_chi2_tolerance = settings.relative_chi2_tolerance;
      s.stop_on_request = true;
      r = factorization_.held().iterate(graph_, s);
    }
  } catch (const Interrupted&) {
    // The estimate moved to the last accepted iterate: the pose covariance must follow it.
    pose_cov_.reset();
    throw;
  }
  poses_since_update_ = 0;
  pose_cov_.reset();
  return r;
}

void GraphBackend::finish() { optimize(); }

void GraphBackend::saveSession(session::SessionState& state) const {
  state.map.landmarks = landmarks();
  std::vector<VariableKey> vars;
  if (!graph_.poses().empty()) vars.push_back(VariableKey::pose(graph_.poses().rbegin()->first));
  for (const auto& [id, l] : graph_.landmarks()) vars.push_back(VariableKey::landmark(id));
  const Eigen::Index m = static_cast<Eigen::Index>(2 * graph_.landmarks().size());
  if (graph_.poses().empty()) {
    state.map.covariance = jointCovariance(vars);
    if (m == 0) state.map.covariance = Eigen::MatrixXd(0, 0);
  } else {
    const Eigen::MatrixXd joint = jointCovariance(vars);
    state.map.covariance = joint.bottomRightCorner(m, m);
    session::RobotBlock robot;
    const auto& x = graph_.poses().rbegin()->second.x;
    robot.pose.mean = Pose2(x);
    robot.pose.cov = joint.topLeftCorner<3, 3>();
    robot.cross_covariance = joint.topRightCorner(3, m);
    state.robot = robot;
  }
  // The graph itself, factor for factor, and the incremental schedule: the next session goes on
  // as the one-shot run would (docs/GRAPH.md "Resuming a session").
  session::SessionSection& s = state.section("backend.graph");
  s.putInteger("next_fresh_id", next_fresh_id_);
  writeGraph(graph_, s);
  s.putInteger("poses_since_update", poses_since_update_);
  s.putInteger("updates", static_cast<std::int64_t>(updates_));
  s.putInteger("poses_dropped", static_cast<std::int64_t>(poses_dropped_));
  std::vector<double> pose_cov;
  if (pose_cov_) pose_cov.assign(pose_cov_->data(), pose_cov_->data() + 9);
  s.putReals("pose_covariance", std::move(pose_cov));
}

void GraphBackend::restoreSession(const session::SessionState& state) {
  const session::SessionSection& s = state.take("backend.graph");
  tracks_ = LandmarkTracks();
  const auto& lm = state.map.landmarks;
  LandmarkId next = s.integer("next_fresh_id", 0);
  for (const LandmarkView& v : lm) {
    tracks_.restore(v);
    next = std::max(next, v.id + 1);
  }
  next_fresh_id_ = next;
  last_ids_.clear();
  pose_cov_.reset();
  start_.reset();
  poses_since_update_ = 0;
  if (hasGraph(s)) {
    // Every field is read and checked whether or not the saved chain goes on.
    const std::size_t max_poses =
        options_.max_poses > 0 ? static_cast<std::size_t>(options_.max_poses) : kMaxSavedPoses;
    FactorGraph saved = readGraph(s, state.header.next_step, max_poses);
    const auto since =
        s.integer("poses_since_update", 0, static_cast<std::int64_t>(saved.poses().size()));
    const auto updates = s.integer("updates", 0);
    const auto dropped = s.integer("poses_dropped", 0);
    const auto& cov = s.reals("pose_covariance");
    if (cov.size() != 0 && cov.size() != 9)
      s.fail("pose_covariance", std::to_string(cov.size()) + " values, expected 0 or 9");
    std::optional<Eigen::Matrix3d> pose_cov;
    if (cov.size() == 9) {
      pose_cov = Eigen::Map<const Eigen::Matrix3d>(cov.data());
      try {
        sqrtInformation(*pose_cov);  // symmetric and positive definite
      } catch (const std::invalid_argument& e) {
        s.fail("pose_covariance", e.what());
      }
    }
    std::vector<LandmarkId> saved_ids, map_ids;
    for (const auto& [id, l] : saved.landmarks()) saved_ids.push_back(id);
    for (const LandmarkView& v : lm) map_ids.push_back(v.id);
    std::sort(map_ids.begin(), map_ids.end());
    if (saved_ids != map_ids)
      s.fail("landmark_ids", "the graph's landmarks are not the map's (section 'landmarks')");
    // The saved chain goes on when the run says the robot starts where it stopped; a robot placed
    // by --wake-up starts a new chain on the map below.
    const bool continues = state.robot_start == session::RobotStart::WhereItStopped &&
                           state.robot && !saved.poses().empty();
    if (continues) {
      // The file's robot is the chain's last pose, written from it: another one is a file edited
      // or mixed up, not a robot placed elsewhere (that is the run's to say).
      const Pose2 last(saved.poses().rbegin()->second.x);
      const Pose2& robot = state.robot->pose.mean;
      if (std::abs(last.x - robot.x) > kSameRobotM || std::abs(last.y - robot.y) > kSameRobotM ||
          std::abs(wrapAngle(last.phi - robot.phi)) > kSameRobotRad)
        s.fail("pose_values",
               "the last pose is not the robot of section 'robot' (the robot goes "
               "on where the session stopped)");
      graph_ = std::move(saved);
      poses_since_update_ = static_cast<int>(since);
      updates_ = static_cast<std::size_t>(updates);
      poses_dropped_ = static_cast<std::size_t>(dropped);
      pose_cov_ = pose_cov;
      return;
    }
  }
  // The map's marginals: each landmark under a prior from its own 2x2 block (an older state, or a
  // robot woken up elsewhere); the first step's pose from the saved or found robot.
  graph_ = FactorGraph();
  for (std::size_t i = 0; i < lm.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(2 * i);
    const Eigen::Matrix2d cov = state.map.covariance.block<2, 2>(k, k);
    graph_.addLandmark(lm[i].id, lm[i].mean);
    try {
      graph_.setLandmarkPrior(lm[i].id, LandmarkPrior::make(lm[i].mean, cov));
    } catch (const std::invalid_argument& e) {
      s.failSection("landmark " + std::to_string(lm[i].id) + ": " + e.what());
    }
  }
  if (state.robot) start_ = state.robot->pose;
}

}  // namespace budget_slam::graph
