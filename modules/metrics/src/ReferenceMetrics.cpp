#include "budget_slam/metrics/ReferenceMetrics.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <unordered_map>

#include "budget_slam/core/AbandonOnStop.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/metrics/GroundTruthErrors.h"

namespace budget_slam::metrics {

ReferenceMetrics compareTrajectories(const std::vector<TrajectoryPoint>& reference,
                                     const std::vector<TrajectoryPoint>& reduced,
                                     const std::vector<LandmarkView>& reference_landmarks,
                                     const std::vector<LandmarkView>& reduced_landmarks) {
  requireFinite(reference, reference_landmarks, "metrics against the reference run");
  requireFinite(reduced, reduced_landmarks, "metrics against the reference run");
  ReferenceMetrics m;
  std::unordered_map<StepIndex, const TrajectoryPoint*> by_step;
  for (const auto& p : reference) by_step[p.step] = &p;
  double sq = 0, heading = 0;
  for (const auto& p : reduced) {
    const auto it = by_step.find(p.step);
    if (it == by_step.end()) continue;
    const auto& r = it->second->pose;
    sq += std::pow(p.pose.x - r.x, 2) + std::pow(p.pose.y - r.y, 2);
    heading += std::abs(mrpt::math::wrapToPi(p.pose.phi - r.phi));
    ++m.poses;
  }
  if (m.poses) {
    m.ate = std::sqrt(sq / m.poses);
    m.are_deg = heading / m.poses * 180.0 / M_PI;
  }
  std::unordered_map<LandmarkId, const LandmarkView*> by_id;
  for (const auto& l : reference_landmarks) by_id[l.id] = &l;
  double lsq = 0;
  for (const auto& l : reduced_landmarks) {
    const auto it = by_id.find(l.id);
    if (it == by_id.end()) continue;
    lsq += (l.mean - it->second->mean).squaredNorm();
    ++m.landmarks;
  }
  if (m.landmarks) m.ale = std::sqrt(lsq / m.landmarks);
  return m;
}

ReferenceMetrics compareWithReference(const Backend& reference, const Backend& reduced,
                                      std::size_t eig_max_rows) {
  const auto ref_lms = reference.landmarks();
  const auto red_lms = reduced.landmarks();
  const auto red_traj = reduced.trajectory();
  ReferenceMetrics m = compareTrajectories(reference.trajectory(), red_traj, ref_lms, red_lms);

  // UD (Eq. 12): the latest pose's covariance determinant, reduced vs reference.
  const double det_ref = reference.robotPose().cov.determinant();
  const double det_red = reduced.robotPose().cov.determinant();
  if (det_ref > 0) {
    m.ud_percent = (det_red - det_ref) / det_ref * 100.0;
    const auto dim = static_cast<double>(reduced.robotPose().cov.rows());
    if (det_red >= 0) m.ud_std_factor = std::pow(det_red / det_ref, 1.0 / (2.0 * dim));
  }

  // EIG (Eq. 11) over the variables both runs hold: the kept poses (only the latest one for the
  // EKF, which keeps no past poses) and the kept landmarks.
  std::vector<VariableKey> vars;
  const bool past_poses = reduced.poseCount() > 1 && reference.poseCount() > 1;
  if (past_poses) {
    for (const auto& p : red_traj) vars.push_back(VariableKey::pose(p.step));
  } else if (!red_traj.empty()) {
    vars.push_back(VariableKey::pose(red_traj.back().step));
  }
  std::map<LandmarkId, bool> in_ref;
  for (const auto& l : ref_lms) in_ref[l.id] = true;
  for (const auto& l : red_lms)
    if (in_ref.count(l.id)) vars.push_back(VariableKey::landmark(l.id));
  std::size_t rows = 0;
  for (const auto& v : vars) rows += v.dim();
  if (rows == 0 || rows > eig_max_rows) return m;
  // Seconds at a few thousand rows: a stop request skips what is left (EIG stays NaN; the
  // caller sees the request), and the eigen-decomposition, which has no place to look at it,
  // is abandoned rather than waited for (core/AbandonOnStop.h).
  try {
    if (Cancellation::requested()) return m;
    Eigen::MatrixXd diff = reference.jointCovariance(vars);
    if (Cancellation::requested()) return m;
    diff -= reduced.jointCovariance(vars);
    const auto extremes = unlessStopped<std::pair<double, double>>(
        [sym = Eigen::MatrixXd(0.5 * (diff + diff.transpose()))] {
          const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym, Eigen::EigenvaluesOnly);
          return std::make_pair(es.eigenvalues().minCoeff(), es.eigenvalues().maxCoeff());
        });
    if (!extremes) return m;
    m.eig_min = extremes->first;
    m.eig_max = extremes->second;
    m.eig_rows = rows;
  } catch (const std::invalid_argument&) {
    // A backend that cannot give one of the variables: EIG stays NaN.
  }
  return m;
}

}  // namespace budget_slam::metrics
