#pragma once
#include <Eigen/Core>
#include <vector>

#include "budget_slam/core/Ids.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/graph/EstimateFactorization.h"
#include "budget_slam/graph/FactorGraph.h"

namespace budget_slam::graph {

/// Data association of the graph backend (docs/GRAPH.md "Data association"): a reading with a
/// sensor landmark ID keeps it; a reading without one (kNoLandmarkId) goes to the landmark of
/// smallest Mahalanobis distance d^2 = e^T S^-1 e, S = R + J Sigma J^T (J = [J_x J_l], Sigma the
/// joint marginal of the pose and the landmark, their correlation included), inside the gate,
/// closest pairs first, at most one reading per landmark per scan.
class NearestNeighbourAssociation {
 public:
  /// `gate_chi2`: GraphSlamOptions::association_gate_chi2 (chi2, 2 dof); `sensor_cov`: R, the
  /// range-bearing covariance [m^2, rad^2].
  NearestNeighbourAssociation(double gate_chi2, const Eigen::Matrix2d& sensor_cov)
      : gate_chi2_(gate_chi2), R_(sensor_cov) {}

  /// One landmark id per reading of `scan`, made at the graph's pose `pose` with the sensor at
  /// `sensor` on the robot. kNoLandmarkId where no landmark is inside the gate (a new landmark).
  /// Only when some reading has no ID does this ask `factorization` for the joint marginal of the
  /// pose and every landmark (one factorization).
  std::vector<LandmarkId> associate(const RangeBearingScan& scan, StepIndex pose,
                                    const Pose2& sensor, const FactorGraph& graph,
                                    EstimateFactorization& factorization) const;

 private:
  double gate_chi2_;
  Eigen::Matrix2d R_;
};

}  // namespace budget_slam::graph
