#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/graph/Factors.h"

namespace budget_slam::graph {

/// A robot pose of the graph (one per kept step).
struct PoseNode {
  Pose2 x = Pose2::Zero();  ///< current estimate
  double t = 0;             ///< timestamp of its step [s]
  std::size_t n_obs = 0;    ///< range-bearing factors on this pose
  /// Odometry from the previous pose of the graph to this one (none on the first pose).
  std::optional<BetweenFactor> odo;
  mutable int col = -1;  ///< first column in the linear system (a cache of FactorGraph)
};

/// One range-bearing factor, stored with its landmark.
struct Observation {
  StepIndex pose = 0;
  RangeBearingFactor f;
};

/// A Gaussian prior on a landmark: what remains of sightings whose poses left the graph
/// (FactorGraph::dropFirstPoses). e = x - mean, whitened by sqrt_info (sqrt_info^T sqrt_info =
/// cov^-1).
struct LandmarkPrior {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  ///< [m]
  Eigen::Matrix2d sqrt_info = Eigen::Matrix2d::Identity();
  static LandmarkPrior make(const Eigen::Vector2d& mean, const Eigen::Matrix2d& cov);
};

/// An R^2 landmark and every factor that touches it.
struct LandmarkNode {
  Eigen::Vector2d x = Eigen::Vector2d::Zero();  ///< current estimate [m]
  std::vector<Observation> obs;
  std::optional<LandmarkPrior> prior;  ///< set when all its sightings' poses left the graph
  mutable int col = -1;  ///< first column in the linear system (a cache of FactorGraph)
};

/// Landmark SLAM factor graph (Choudhary et al. Eq. 1-3): a prior on the first pose, one odometry
/// factor between consecutive kept poses, range-bearing factors between poses and landmarks.
/// Poses are keyed by step index, landmarks by id. The structure is a chain of poses, so removing
/// a pose composes its two odometry factors (marginalizePose).
///
/// Linear system: with every factor whitened (r = S e, A = S de/dx), H = sum A^T A and
/// g = sum A^T r; the Gauss-Newton step solves H dx = -g. Columns: poses in step order, then
/// landmarks in id order (CHOLMOD reorders for fill).
class FactorGraph {
 public:
  // -- building --
  /// The first pose with its prior. Throws std::logic_error if the graph already has poses.
  void addFirstPose(StepIndex step, double t, const Pose2& x, const PriorFactor& prior);
  /// A pose after the last one, tied to it by `odo`. Throws std::logic_error if `step` is not
  /// after the last pose.
  void addPose(StepIndex step, double t, const Pose2& x, const BetweenFactor& odo);
  /// Throws std::logic_error if the id exists.
  void addLandmark(LandmarkId id, const Eigen::Vector2d& x);
  /// Throws std::out_of_range if the pose or landmark is unknown.
  void addObservation(StepIndex pose, LandmarkId id, const RangeBearingFactor& f);

  /// Deletes the landmark and its factors; throws std::out_of_range if unknown.
  void removeLandmark(LandmarkId id);
  /// True when the pose has no landmark factor and sits between two poses (it then carries only
  /// its two odometry factors and can leave by composing them).
  bool canMarginalizePose(StepIndex step) const;
  /// Replaces x_{i} -> x_j -> x_k by the composed factor x_i -> x_k (composeBetween) and deletes
  /// x_j. Throws std::logic_error unless canMarginalizePose(step).
  void marginalizePose(StepIndex step);
  /// Bounded graph: deletes the first `count` poses (fewer than the graph has) and every
  /// range-bearing factor on them, and puts `next_prior` on the new first pose in place of its
  /// odometry factor. A landmark left without factors stays unconstrained until it gets a prior
  /// (setLandmarkPrior): the caller does that first (GraphBackend).
  void dropFirstPoses(std::size_t count, const PriorFactor& next_prior);
  /// Replaces any prior on the landmark; throws std::out_of_range if unknown.
  void setLandmarkPrior(LandmarkId id, const LandmarkPrior& prior);

  // -- access --
  const std::map<StepIndex, PoseNode>& poses() const { return poses_; }
  const std::map<LandmarkId, LandmarkNode>& landmarks() const { return landmarks_; }
  const PriorFactor& prior() const { return prior_; }
  bool hasPose(StepIndex s) const { return poses_.count(s) != 0; }
  bool hasLandmark(LandmarkId id) const { return landmarks_.count(id) != 0; }
  const PoseNode& pose(StepIndex s) const { return poses_.at(s); }
  const LandmarkNode& landmark(LandmarkId id) const { return landmarks_.at(id); }
  /// A writable estimate (counts as a change of values: revision() moves).
  Pose2& poseValue(StepIndex s) {
    ++revision_;
    return poses_.at(s).x;
  }
  Eigen::Vector2d& landmarkValue(LandmarkId id) {
    ++revision_;
    return landmarks_.at(id).x;
  }
  std::size_t factorCount() const;

  /// Bumped by every change of variables or factors (not of values): the sparsity pattern of H,
  /// and so CHOLMOD's symbolic analysis, depends only on it.
  std::uint64_t structureVersion() const { return structure_version_; }
  /// Bumped by every change of variables, factors or values: H at the estimate, and so a
  /// factorization of it, is unchanged while this is (EstimateFactorization).
  std::uint64_t revision() const { return revision_; }

  // -- linear system --
  /// Size of the state (3 a pose, 2 a landmark).
  int dim() const;
  /// First column of a variable; throws std::out_of_range if unknown.
  int column(const VariableKey& v) const;
  /// First column of every variable in column order (poses, then landmarks), then dim(): the
  /// variable partition of H's columns (SparseCholesky orders variables, not scalars).
  const std::vector<int>& variableStarts() const;
  /// Sum of squared whitened residuals (twice the negative log-likelihood up to a constant).
  double chi2() const;
  /// H (lower triangle only, as CHOLMOD reads it) and g at the current estimate; with `chi2`,
  /// also the chi2() of that estimate from the same residuals (no second pass over the factors).
  void linearize(Eigen::SparseMatrix<double>* H, Eigen::VectorXd* g, double* chi2 = nullptr) const;
  /// x <- x + dx (yaw wrapped), dx laid out as column().
  void retract(const Eigen::VectorXd& dx);
  /// The current estimate stacked as column() (for tests and comparisons).
  Eigen::VectorXd values() const;
  /// Inverse of values().
  void setValues(const Eigen::VectorXd& v);

 private:
  /// The variables in column order with a dense step -> pose lookup, rebuilt once per structure
  /// change: every pass over the factors (linearize, chi2, retract) walks these arrays instead of
  /// the maps, and a sighting finds its pose by an index instead of a tree search. The pointers
  /// are to this graph's own map nodes (std::map never moves them), so a copy of the graph starts
  /// with an empty layout and builds its own.
  struct Layout {
    std::uint64_t version = ~std::uint64_t(0);
    int dim = 0;
    std::vector<PoseNode*> poses;          ///< in step order
    std::vector<LandmarkNode*> landmarks;  ///< in id order
    StepIndex first_step = 0;
    std::vector<PoseNode*> by_step;  ///< by_step[s - first_step]; nullptr for a step not kept
    std::vector<int> starts;         ///< variableStarts()
    Layout() = default;
    Layout(const Layout&) {}
    Layout& operator=(const Layout&) {
      version = ~std::uint64_t(0);
      return *this;
    }
    const PoseNode& pose(StepIndex s) const { return *by_step[s - first_step]; }
  };

  void changed();
  const Layout& layout() const;

  std::map<StepIndex, PoseNode> poses_;
  std::map<LandmarkId, LandmarkNode> landmarks_;
  PriorFactor prior_;
  std::uint64_t structure_version_ = 0;
  std::uint64_t revision_ = 0;
  mutable Layout layout_;
};

}  // namespace budget_slam::graph
