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
#include "budget_slam/graph/GraphFactor.h"

namespace budget_slam::graph {

/// A robot pose of the graph (one per kept step).
struct PoseNode {
  /// Current estimate: the pose's parameters (x [m], y [m], phi [rad]), Pose2::vector(), the
  /// solver's values as a landmark's are (Gauss-Newton steps add to them, the heading wrapped).
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  double t = 0;           ///< timestamp of its step [s]
  std::size_t n_obs = 0;  ///< range-bearing factors on this pose
  /// Odometry from the previous pose of the graph to this one (none on the first pose).
  std::optional<BetweenFactor> odo;
  FactorId odo_id = 0;      ///< its identity (GraphFactor::id)
  VariableIndex index = 0;  ///< the pose's identity (FactorGraph::variableIndices)
  mutable int col = -1;     ///< first column in the linear system (a cache of FactorGraph)
};

/// One range-bearing factor, stored with its landmark.
struct Observation {
  StepIndex pose = 0;
  RangeBearingFactor f;
  FactorId id = 0;  ///< its identity (GraphFactor::id)
};

/// An R^2 landmark and every factor that touches it.
struct LandmarkNode {
  Eigen::Vector2d x = Eigen::Vector2d::Zero();  ///< current estimate [m]
  std::vector<Observation> obs;
  std::optional<LandmarkPrior> prior;  ///< set when all its sightings' poses left the graph
  FactorId prior_id = 0;               ///< its identity (GraphFactor::id)
  VariableIndex index = 0;             ///< the landmark's identity (FactorGraph::variableIndices)
  mutable int col = -1;  ///< first column in the linear system (a cache of FactorGraph)
};

/// One change of a FactorGraph's variables or factors (FactorGraph::changesSince), in the order
/// made: what a held factorization must fold in to stay the factor of the graph.
struct GraphChange {
  enum class Kind : std::uint8_t { AddVariable, RemoveVariable, AddFactor, RemoveFactor };
  Kind kind = Kind::AddVariable;
  VariableKey variable;     ///< AddVariable, RemoveVariable
  VariableIndex index = 0;  ///< AddVariable, RemoveVariable: the variable's index
  GraphFactor factor;       ///< AddFactor: the factor as added; RemoveFactor: only its id is set
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
  Eigen::Vector3d& poseValue(StepIndex s) {
    valuesChanged();
    return poses_.at(s).x;
  }
  Eigen::Vector2d& landmarkValue(LandmarkId id) {
    valuesChanged();
    return landmarks_.at(id).x;
  }
  std::size_t factorCount() const;

  /// Bumped by every change of variables or factors (not of values): the sparsity pattern of H,
  /// and so CHOLMOD's symbolic analysis, depends only on it.
  std::uint64_t structureVersion() const { return structure_version_; }
  /// Bumped by every change of the set of variables (and so of the column layout).
  std::uint64_t variablesVersion() const { return variables_version_; }
  /// Bumped by every change of variables, factors or values: H at the estimate, and so a
  /// factorization of it, is unchanged while this is (EstimateFactorization).
  std::uint64_t revision() const { return revision_; }
  /// Bumped by every change of the values of existing variables (retract, setValues,
  /// poseValue, landmarkValue); adding a variable is a change of structure, not of values.
  std::uint64_t valuesVersion() const { return values_version_; }

  // -- change journal (the held factorization follows the graph through it) --
  /// This graph object's identity: a copy gets a new one, since its later changes are its own.
  std::uint64_t lineage() const { return lineage_.id; }
  /// Changes made to this graph so far (the sequence number of the next one).
  std::uint64_t changeCount() const { return journal_start_ + journal_.size(); }
  /// The changes made since the sequence number `seq` (an earlier changeCount()), oldest first,
  /// in [*first, *last). False when the journal no longer holds them all: it keeps at least the
  /// last kJournalCapacity changes, so memory stays bounded; the reader then starts afresh.
  bool changesSince(std::uint64_t seq, const GraphChange** first, const GraphChange** last) const;
  static constexpr std::size_t kJournalCapacity = 2048;
  /// Every factor of the graph as a value: the prior, the odometry in step order, then each
  /// landmark's sightings and prior in id order.
  std::vector<GraphFactor> factors() const;

  // -- linear system --
  /// Size of the state (3 a pose, 2 a landmark).
  int dim() const;
  /// First column of a variable; throws std::out_of_range if unknown.
  int column(const VariableKey& v) const;
  /// First column of every variable in column order (poses, then landmarks), then dim(): the
  /// variable partition of H's columns (SparseCholesky orders variables, not scalars).
  const std::vector<int>& variableStarts() const;
  /// Each variable's index in column order (poses, then landmarks): its identity while it is in
  /// the graph, dense from 0 (a removed variable's index is given out again), that a held
  /// factorization keys its per-variable data by.
  const std::vector<VariableIndex>& variableIndices() const;
  /// One more than the largest variable index given out (at most the peak variable count).
  VariableIndex variableIndexBound() const { return next_variable_index_; }
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
  /// The variables in column order with a dense step -> pose lookup, rebuilt once per change of
  /// the variable set (grown in place when a pose or landmark is appended): every pass over the
  /// factors (linearize, chi2, retract) walks these arrays instead of the maps, and a sighting
  /// finds its pose by an index instead of a tree search. The pointers
  /// are to this graph's own map nodes (std::map never moves them), so a copy of the graph starts
  /// with an empty layout and builds its own.
  struct Layout {
    std::uint64_t version = ~std::uint64_t(0);
    int dim = 0;
    std::vector<PoseNode*> poses;          ///< in step order
    std::vector<LandmarkNode*> landmarks;  ///< in id order
    StepIndex first_step = 0;
    std::vector<PoseNode*> by_step;      ///< by_step[s - first_step]; nullptr for a step not kept
    std::vector<int> starts;             ///< variableStarts()
    std::vector<VariableIndex> indices;  ///< variableIndices()
    Layout() = default;
    Layout(const Layout&) {}
    Layout& operator=(const Layout&) {
      version = ~std::uint64_t(0);
      return *this;
    }
    const PoseNode& pose(StepIndex s) const { return *by_step[s - first_step]; }
  };

  /// A fresh identity for every graph object; a copy draws a new one.
  struct Lineage {
    std::uint64_t id = next();
    Lineage() = default;
    Lineage(const Lineage&) : id(next()) {}
    Lineage& operator=(const Lineage&) {
      id = next();
      return *this;
    }
    static std::uint64_t next();
  };

  void changed();
  /// The set of variables (and so the column layout) changed.
  void variablesChanged() { ++variables_version_; }
  /// A pose just appended after the last one: the layout grows in place when it is current
  /// (O(variables) in contiguous arrays, not a walk of the maps). Marks the variables changed.
  void appendToLayout(PoseNode* pose);
  /// A landmark just added, `position` landmarks before it in id order: the layout grows in place
  /// when it is current, as for a pose. Marks the variables changed.
  void insertIntoLayout(LandmarkNode* landmark, std::size_t position);
  /// A landmark about to be erased: when the layout is current it shrinks in place (the
  /// landmarks after it move 2 columns down; O(variables) in contiguous arrays, no walk of the
  /// maps), so a capped map's evictions do not rebuild the layout of a long trajectory. Marks the
  /// variables changed.
  void removeFromLayout(const LandmarkNode* landmark);
  VariableIndex newVariableIndex();
  void freeVariableIndex(VariableIndex v);
  void valuesChanged() {
    ++revision_;
    ++values_version_;
  }
  void record(GraphChange c);
  void recordVariable(GraphChange::Kind kind, const VariableKey& v, VariableIndex index);
  void recordRemoval(FactorId id);
  void recordAddition(GraphFactor f);
  using PoseIt = std::map<StepIndex, PoseNode>::const_iterator;
  using LandmarkIt = std::map<LandmarkId, LandmarkNode>::const_iterator;
  GraphFactor posePriorFactor() const;
  GraphFactor odometryFactor(PoseIt from, PoseIt to) const;
  GraphFactor sightingFactor(LandmarkIt l, const Observation& o) const;
  GraphFactor landmarkPriorFactor(LandmarkIt l) const;
  const Layout& layout() const;

  std::map<StepIndex, PoseNode> poses_;
  std::map<LandmarkId, LandmarkNode> landmarks_;
  PriorFactor prior_;
  FactorId prior_id_ = 0;
  FactorId next_factor_id_ = 1;
  VariableIndex next_variable_index_ = 0;
  std::vector<VariableIndex> free_indices_;  ///< of removed variables, given out again
  std::uint64_t variables_version_ = 0;      ///< moves with every change of the variable set
  std::uint64_t structure_version_ = 0;
  std::uint64_t revision_ = 0;
  std::uint64_t values_version_ = 0;
  std::vector<GraphChange> journal_;  ///< changes journal_start_ ... changeCount() - 1
  std::uint64_t journal_start_ = 0;
  Lineage lineage_;
  mutable Layout layout_;
};

}  // namespace budget_slam::graph
