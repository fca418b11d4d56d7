#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <variant>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"
#include "budget_slam/graph/Factors.h"

namespace budget_slam::graph {

/// A factor's identity in its FactorGraph: never reused within a graph and its copies.
using FactorId = std::uint64_t;
/// A variable's identity in its FactorGraph while it is there, dense from 0 (a removed variable's
/// index is given out again; FactorGraph::variableIndices).
using VariableIndex = std::uint32_t;

/// One factor of a FactorGraph with the variables it ties, as a value: the graph's change journal
/// (FactorGraph::changesSince) hands added factors out in this form, and the held factorization
/// (IncrementalFactorization) keeps each one it has folded in.
struct GraphFactor {
  enum class Kind : std::uint8_t { PosePrior, Odometry, RangeBearing, LandmarkPrior };
  Kind kind = Kind::PosePrior;
  FactorId id = 0;
  StepIndex pose = 0;       ///< PosePrior, RangeBearing: the pose; Odometry: the later pose
  StepIndex from = 0;       ///< Odometry: the earlier pose
  LandmarkId landmark = 0;  ///< RangeBearing, LandmarkPrior
  /// The variables' indices in the graph, in the order of variable(k).
  std::array<VariableIndex, 2> vars{{0, 0}};
  std::variant<PriorFactor, BetweenFactor, RangeBearingFactor, LandmarkPrior> f;

  static GraphFactor posePrior(FactorId id, StepIndex pose, const PriorFactor& f);
  static GraphFactor odometry(FactorId id, StepIndex from, StepIndex to, const BetweenFactor& f);
  static GraphFactor rangeBearing(FactorId id, StepIndex pose, LandmarkId landmark,
                                  const RangeBearingFactor& f);
  static GraphFactor landmarkPrior(FactorId id, LandmarkId landmark, const LandmarkPrior& f);

  /// 1 or 2: the variables in the order of the Jacobian's column blocks (LinearFactor).
  int variableCount() const;
  VariableKey variable(int k) const;
};

/// A factor linearized at given variable values, whitened: r = S e, A = S de/dx with the
/// variables' parameter blocks side by side (3 columns a pose, 2 a landmark). Its part of the
/// normal equations is H += A^T A, g += A^T r, chi2 += |r|^2.
struct LinearFactor {
  int rows = 0;  ///< 2 or 3
  int cols = 0;  ///< 2 to 6
  Eigen::Matrix<double, 3, 6> A = Eigen::Matrix<double, 3, 6>::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
};

/// Linearizes `f` with its first variable at x0 and its second (if any) at x1 (a landmark reads
/// the first two entries). The same arithmetic as FactorGraph::linearize, factor by factor.
LinearFactor linearize(const GraphFactor& f, const Eigen::Vector3d& x0,
                       const Eigen::Vector3d& x1 = Eigen::Vector3d::Zero());

}  // namespace budget_slam::graph
