#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <map>
#include <optional>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/BackendRegistry.h"
#include "budget_slam/core/LandmarkTracks.h"
#include "budget_slam/graph/EstimateFactorization.h"
#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/GraphOptions.h"
#include "budget_slam/graph/Solver.h"
#include "budget_slam/graph/SparseCholesky.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::graph {

/// Landmark graph SLAM behind the Backend interface (`--backend graph`; docs/GRAPH.md). Full
/// smoothing over every kept pose; the Cholesky factor of H is held between updates and changed
/// where the graph changes (IncrementalFactorization, docs/GRAPH.md "Held factor"), and the
/// covariances and information gains at the current estimate read it (EstimateFactorization). Bad
/// step data (a reading the graph cannot use) is an InputError naming the step and the reading.
class GraphBackend : public Backend, public PoseHistoryBackend, public session::SessionStateOwner {
 public:
  /// Reads [GraphSLAM] and the sensor noise keys of [RangeBearingKFSLAM].
  explicit GraphBackend(const mrpt::config::CConfigFileBase& ini);
  GraphBackend(const GraphSlamOptions& options, const RangeBearingNoise& noise);

  static constexpr const char* kName = "graph";

  /// Its registry entry: name, summary, [GraphSLAM] and the noise keys, factory.
  static BackendEntry entry();

  std::string name() const override { return kName; }
  /// Adds the step's pose (odometry factor from the previous pose; the first step's pose gets the
  /// prior at the origin composed with its odometry), its range-bearing factors and new
  /// landmarks, then runs the incremental schedule (GraphSlamOptions).
  void process(const Step& step) override;
  std::vector<LandmarkView> landmarks() const override;
  /// From the sighting bookkeeping, without the marginals landmarks() computes; sorted by id.
  std::vector<LandmarkId> observedAt(StepIndex step) const override;
  std::size_t landmarkCount() const override { return graph_.landmarks().size(); }
  PoseEstimate robotPose() const override;
  std::vector<TrajectoryPoint> trajectory() const override;
  std::size_t poseCount() const override { return graph_.poses().size(); }
  std::vector<LandmarkId> lastAssociation() const override { return last_ids_; }
  void removeLandmark(LandmarkId id) override;
  std::vector<double> informationGain(const std::vector<LandmarkId>& ids) const override;
  Eigen::Matrix2d landmarkCovariance(LandmarkId id) const override;
  Eigen::MatrixXd jointCovariance(const std::vector<VariableKey>& vars) const override;
  /// PoseHistoryBackend: a pose tied only by odometry goes, its two odometry factors composed.
  std::size_t marginalizePosesWithoutLandmarks(std::size_t keep_last) override;
  /// PoseHistoryBackend: solves to the batch optimum.
  void finish() override;
  /// Deep copy of the graph, the estimate, the held factor and the bookkeeping (sightings,
  /// fresh-id counter, incremental schedule, latest pose covariance).
  std::unique_ptr<Backend> clone() const override;

  /// The map as the joint marginal of every landmark and the latest pose at the current estimate
  /// (the robot with its cross-covariance), and section `backend.graph`: the next fresh id, the
  /// whole graph factor for factor (writeGraph) and the incremental schedule (poses since the last
  /// update, the latest pose's covariance between updates).
  void saveSession(session::SessionState& state) const override;
  /// The saved graph as it was, when the robot continues where the session stopped
  /// (state.robot_start, told by the run): the next session's steps are the one-shot run's (a
  /// `[robot]` pose other than the chain's last is an InputError). When the robot was placed
  /// elsewhere (session::RobotStart::Placed: --wake-up), or
  /// the state holds no graph (written before it was saved whole), a new graph on the saved map:
  /// each landmark with a prior from its marginal (2x2 block of the saved joint covariance; the
  /// correlations are not kept), and the next step's pose from the robot pose and its marginal
  /// composed with the step's odometry. docs/GRAPH.md "Resuming a session".
  void restoreSession(const session::SessionState& state) override;

  /// Solves to convergence now (what finish() does); returns the solver's report.
  SolveReport optimize();
  const FactorGraph& graph() const { return graph_; }
  const GraphSlamOptions& options() const { return options_; }
  const RangeBearingNoise& noise() const { return noise_; }
  /// Incremental updates run so far (for reports).
  std::size_t updateCount() const { return updates_; }
  /// Poses removed by the bounded graph (GraphSlamOptions::max_poses) so far.
  std::size_t posesDropped() const { return poses_dropped_; }
  /// The held factor and its queries (benchmarks and tests compare it with a fresh
  /// factorization; a query folds in the changes since the last one, hence mutable).
  EstimateFactorization& factorization() const { return factorization_; }
  /// What the held factor did so far: rebuilds, fresh orderings, in-place changes.
  const IncrementalStats& heldFactorStats() const { return factorization_.held().stats(); }

 private:
  /// clone(): everything but the factorization caches (CHOLMOD objects are never shared).
  GraphBackend(const GraphBackend& other);
  GraphBackend& operator=(const GraphBackend&) = delete;

  BetweenFactor odometryFactor(const Step& step) const;
  Eigen::Matrix2d sensorCovariance() const;
  /// A few warm-started Gauss-Newton iterations (GraphSlamOptions::incremental_iterations).
  void incrementalUpdate();
  /// GraphSlamOptions::max_poses: the oldest poses leave when the graph holds more.
  void boundPoses();

  GraphSlamOptions options_;
  RangeBearingNoise noise_;
  FactorGraph graph_;
  LandmarkTracks tracks_;  ///< sightings of every landmark (Hochdorfer & Schlegel Eq. 1-2)
  LandmarkId next_fresh_id_ = 0;
  std::vector<LandmarkId> last_ids_;  ///< lastAssociation(): one id a reading of the last step
  int poses_since_update_ = 0;
  std::size_t updates_ = 0;
  std::size_t poses_dropped_ = 0;

  /// The held factor of H at the current estimate: the Gauss-Newton updates run on it and every
  /// covariance and gain query reads it, folding in whatever changed since (robotPose() is exact
  /// when it is current).
  mutable EstimateFactorization factorization_;
  /// Latest pose covariance between factorizations (GraphSlamOptions::exact_pose_covariance).
  mutable std::optional<Eigen::Matrix3d> pose_cov_;
  std::optional<PoseEstimate> start_;  ///< a resumed session's start (restoreSession, setStart)
};

}  // namespace budget_slam::graph
