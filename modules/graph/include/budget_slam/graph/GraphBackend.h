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
/// smoothing over every kept pose; covariances and information gains are evaluated at the current
/// estimate from one CHOLMOD factorization (EstimateFactorization), rebuilt on demand after any
/// change of the graph. Bad step data (a reading the graph cannot use) is an InputError naming the
/// step and the reading.
class GraphBackend : public Backend, public session::SessionStateOwner {
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
  std::size_t marginalizePosesWithoutLandmarks(std::size_t keep_last) override;
  void finish() override;
  /// Deep copy of the graph, the estimate and the bookkeeping (sightings, fresh-id counter,
  /// incremental schedule, latest pose covariance). The CHOLMOD factorizations are not copied:
  /// the copy rebuilds them lazily at its first query, with the same result.
  std::unique_ptr<Backend> clone() const override;

  /// Solves to convergence now (what finish() does); returns the solver's report.
  /// The map as the joint marginal of every landmark and the latest pose at the current estimate
  /// (the robot with its cross-covariance), and section `backend.graph` (the next fresh id).
  void saveSession(session::SessionState& state) const override;
  /// A new graph on the saved map: each landmark with a prior from its marginal (2x2 block of the
  /// saved joint covariance; the correlations between landmarks and with the robot are not
  /// kept), and the next step's pose from the saved robot pose and its marginal composed with the
  /// step's odometry (waking up: the pose found). docs/GRAPH.md "Resuming a session".
  void restoreSession(const session::SessionState& state) override;

  SolveReport optimize();
  const FactorGraph& graph() const { return graph_; }
  const GraphSlamOptions& options() const { return options_; }
  const RangeBearingNoise& noise() const { return noise_; }
  /// Incremental updates run so far (for reports).
  std::size_t updateCount() const { return updates_; }
  /// Poses removed by the bounded graph (GraphSlamOptions::max_poses) so far.
  std::size_t posesDropped() const { return poses_dropped_; }
  /// Fresh and kept orderings of the solver's factorizations (IncrementalOrdering).
  const IncrementalOrdering& solverOrdering() const { return solver_ordering_; }

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
  SparseCholesky solver_chol_;
  IncrementalOrdering solver_ordering_;

  /// H at the current estimate, factorized on demand for every covariance and gain query; it
  /// knows the graph state it is of (robotPose() is exact when one was computed for this state).
  mutable EstimateFactorization factorization_;
  /// Latest pose covariance between factorizations (GraphSlamOptions::exact_pose_covariance).
  mutable std::optional<Eigen::Matrix3d> pose_cov_;
  std::optional<PoseEstimate> start_;  ///< a resumed session's start (restoreSession, setStart)
};

}  // namespace budget_slam::graph
