#include "budget_slam/graph/NearestNeighbourAssociation.h"

#include <Eigen/Cholesky>
#include <algorithm>

#include "budget_slam/graph/Factors.h"

namespace budget_slam::graph {

std::vector<LandmarkId> NearestNeighbourAssociation::associate(
    const RangeBearingScan& scan, StepIndex pose, const Pose2& sensor, const FactorGraph& graph,
    EstimateFactorization& factorization) const {
  std::vector<LandmarkId> ids(scan.readings.size(), kNoLandmarkId);
  bool any = false;
  for (std::size_t r = 0; r < scan.readings.size(); ++r) {
    ids[r] = scan.readings[r].id;
    any |= ids[r] == kNoLandmarkId;
  }
  if (!any || graph.landmarks().empty()) return ids;
  // Joint marginal of the new pose and every landmark (one factorization; only rawlogs without
  // landmark IDs pay for it): the innovation covariance S = R + J Sigma J^T, J = [J_x J_l],
  // includes the pose uncertainty and its correlation with each landmark.
  std::vector<VariableKey> vars{VariableKey::pose(pose)};
  for (const auto& [id, l] : graph.landmarks()) vars.push_back(VariableKey::landmark(id));
  // At the held factor's linearization point: the update just run leaves it one step behind the
  // estimate, the gate's accuracy (a relinearization per step would cost more than it moves).
  const Eigen::MatrixXd Sigma = factorization.jointMarginal(graph, vars, /*at_estimate=*/false);
  const Pose2 x(graph.pose(pose).x);
  struct Pair {
    double d2;
    std::size_t r;
    LandmarkId id;
  };
  std::vector<Pair> pairs;
  for (std::size_t r = 0; r < scan.readings.size(); ++r) {
    if (ids[r] != kNoLandmarkId) continue;
    const RangeBearingFactor f =
        RangeBearingFactor::make(scan.readings[r].range, scan.readings[r].yaw, sensor, R_);
    int k = 3;
    for (const auto& [id, l] : graph.landmarks()) {
      Eigen::Matrix<double, 2, 3> Jx;
      Eigen::Matrix2d Jl;
      const Eigen::Vector2d e = f.error(x, l.x, &Jx, &Jl);
      Eigen::Matrix<double, 2, 5> J;
      J << Jx, Jl;
      Eigen::Matrix<double, 5, 5> P;
      P << Sigma.topLeftCorner<3, 3>(), Sigma.block<3, 2>(0, k), Sigma.block<2, 3>(k, 0),
          Sigma.block<2, 2>(k, k);
      const Eigen::Matrix2d S = R_ + J * P * J.transpose();
      const double d2 = e.dot(S.ldlt().solve(e));
      if (d2 < gate_chi2_) pairs.push_back({d2, r, id});
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
  return ids;  // still kNoLandmarkId: a new landmark (the caller gives it a fresh id)
}

}  // namespace budget_slam::graph
