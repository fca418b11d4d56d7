#include "budget_slam/reducers/MovedLandmarks.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/core/RangeBearingModel.h"

namespace budget_slam::reducers {

namespace {

/// One reading of the step of a landmark in the map, tested against its estimate.
struct Tested {
  LandmarkId id = kNoLandmarkId;
  bool tested = false;  ///< false: the test is undefined (the landmark at the sensor)
  bool passes = true;   ///< inside the gate
  double nis = 0;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< where the reading puts the landmark [m]
  Eigen::Matrix2d point_cov = Eigen::Matrix2d::Identity();
};

}  // namespace

bool MovedLandmarks::coherent(std::vector<MovedEvidence>& evidence) const {
  // The pieces must put the landmark at one place: each within the gate of their mean, under its
  // own covariance. An incoherent piece is the oldest that no longer fits: drop from the front.
  while (evidence.size() >= 2) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& e : evidence) mean += e.point;
    mean /= static_cast<double>(evidence.size());
    const bool all_in = std::all_of(evidence.begin(), evidence.end(), [&](const MovedEvidence& e) {
      const Eigen::Vector2d d = e.point - mean;
      return d.dot(e.point_cov.ldlt().solve(d)) <= settings_.gate_chi2;
    });
    if (all_in) break;
    evidence.erase(evidence.begin());
  }
  return evidence.size() >= settings_.readings;
}

MovedScreening MovedLandmarks::screen(const Backend& backend, const Step& step,
                                      std::optional<StepIndex> last_step) {
  MovedScreening out;
  if (!step.scan || step.scan->readings.empty()) return out;
  const RangeBearingScan& scan = *step.scan;

  // The landmarks of the map the step reads, each once, in the order first read.
  std::map<LandmarkId, std::size_t> column;  // id -> index among the read landmarks
  std::vector<LandmarkView> read;
  {
    const std::vector<LandmarkView> map = backend.landmarks();
    std::map<LandmarkId, const LandmarkView*> by_id;
    for (const LandmarkView& l : map) by_id.emplace(l.id, &l);
    for (const RangeBearingReading& r : scan.readings) {
      const auto it = by_id.find(r.id);
      if (r.id == kNoLandmarkId || it == by_id.end() || column.count(r.id)) continue;
      column.emplace(r.id, read.size());
      read.push_back(*it->second);
    }
  }
  if (read.empty()) return out;

  // Joint covariance of the latest pose and the read landmarks; their marginals when the
  // backend cannot say (no latest step known, e.g. the first step after a wake-up).
  const auto n = static_cast<Eigen::Index>(read.size());
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(3 + 2 * n, 3 + 2 * n);
  const PoseEstimate pose = backend.robotPose();
  bool joint = false;
  if (last_step) try {
      std::vector<VariableKey> vars = {VariableKey::pose(*last_step)};
      for (const LandmarkView& l : read) vars.push_back(VariableKey::landmark(l.id));
      P = backend.jointCovariance(vars);
      joint = P.rows() == 3 + 2 * n && P.allFinite();
    } catch (const std::exception&) {
      joint = false;
    }
  if (!joint) {
    P.setZero(3 + 2 * n, 3 + 2 * n);
    P.topLeftCorner<3, 3>() = pose.cov;
    for (Eigen::Index j = 0; j < n; ++j) P.block<2, 2>(3 + 2 * j, 3 + 2 * j) = read[j].cov;
  }

  // The pose predicted with the step's odometry (first order): x- = x (+) u.
  const Pose2 x = pose.mean;
  Pose2 u;
  Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();
  if (step.odometry) {
    u = step.odometry->mean;
    Q = step.odometry->cov;
  }
  Eigen::Matrix3d Jx, Ju;
  const Pose2 xp = compose(x, u, &Jx, &Ju);
  P.topRows(3) = (Jx * P.topRows(3)).eval();
  P.leftCols(3) = (P.leftCols(3) * Jx.transpose()).eval();
  P.topLeftCorner<3, 3>() += Ju * Q * Ju.transpose();
  const Pose2 sensor(scan.sensor_pose_on_robot.x, scan.sensor_pose_on_robot.y,
                     scan.sensor_pose_on_robot.yaw);
  const Eigen::Matrix2d R = Eigen::Vector2d(settings_.std_range * settings_.std_range,
                                            settings_.std_bearing * settings_.std_bearing)
                                .asDiagonal();
  const Eigen::Matrix3d Prr = P.topLeftCorner<3, 3>();

  std::vector<Tested> tests;
  for (const RangeBearingReading& r : scan.readings) {
    const auto c = column.find(r.id);
    if (c == column.end()) continue;
    Tested t;
    t.id = r.id;
    const auto j = static_cast<Eigen::Index>(3 + 2 * c->second);
    const Eigen::Vector2d mean = read[c->second].mean;
    const Eigen::Vector2d sensor_at = xp.translation() + xp.rotation() * sensor.translation();
    if ((mean - sensor_at).norm() < 1e-9 || !(r.range > 0)) {
      tests.push_back(t);
      continue;
    }
    const RangeBearingPrediction p = predictRangeBearing(xp, sensor, mean);
    const Eigen::Vector2d nu(r.range - p.z(0), std::remainder(r.yaw - p.z(1), 2 * M_PI));
    const Eigen::Matrix2d cross = p.H_robot * P.block<3, 2>(0, j) * p.H_landmark.transpose();
    const Eigen::Matrix2d S = p.H_robot * Prr * p.H_robot.transpose() + cross + cross.transpose() +
                              p.H_landmark * P.block<2, 2>(j, j) * p.H_landmark.transpose() + R;
    t.nis = nu.dot(S.ldlt().solve(nu));
    t.tested = std::isfinite(t.nis);
    t.passes = !t.tested || t.nis <= settings_.gate_chi2;
    // Where the reading puts the landmark, and the covariance of that point from the pose's
    // and the reading's (first order).
    Eigen::Matrix2d dq;  // d(q)/d(range, bearing)
    const Eigen::Vector2d q = readingPoint(r.range, r.yaw, sensor, nullptr, &dq);
    const Eigen::Matrix2d rot = xp.rotation();
    t.point = xp.translation() + rot * q;
    Eigen::Matrix<double, 2, 3> Gr;
    Gr << 1, 0, -rot(1, 0) * q.x() - rot(0, 0) * q.y(),  //
        0, 1, rot(0, 0) * q.x() - rot(1, 0) * q.y();
    const Eigen::Matrix2d Gz = rot * dq;
    t.point_cov = Gr * Prr * Gr.transpose() + Gz * R * Gz.transpose();
    tests.push_back(t);
  }

  // Suspects as the step found them: their readings do not vouch for the rest of the view.
  std::set<LandmarkId> suspect_before;
  for (const auto& [id, e] : suspects_) suspect_before.insert(id);
  std::set<LandmarkId> gathered;  // landmarks given evidence at this step
  for (std::size_t k = 0; k < tests.size(); ++k) {
    const Tested& t = tests[k];
    if (!t.tested) continue;
    if (t.passes) {
      suspects_.erase(t.id);  // consistent with its estimate again: not moved
      continue;
    }
    std::size_t agree = 0, disagree = 0;
    for (std::size_t m = 0; m < tests.size(); ++m) {
      const Tested& o = tests[m];
      if (m == k || o.id == t.id || !o.tested || suspect_before.count(o.id)) continue;
      ++(o.passes ? agree : disagree);
    }
    const bool view_agrees = agree >= settings_.min_agreeing && agree > disagree;
    const bool suspect = suspects_.count(t.id) > 0;
    if (!view_agrees) {
      // The pose may be off, not the landmark: no evidence. A suspect is still held.
      if (suspect) out.held.insert(t.id);
      continue;
    }
    if (!suspect && suspects_.size() >= settings_.max_suspects) continue;  // bounded: fuse
    std::vector<MovedEvidence>& evidence = suspects_[t.id];
    out.held.insert(t.id);
    const bool new_place =
        std::all_of(evidence.begin(), evidence.end(), [&](const MovedEvidence& e) {
          return (e.robot - xp.translation()).norm() >= settings_.place_distance;
        });
    if (!new_place) continue;
    evidence.push_back({step.index, xp.translation(), t.point, t.point_cov, t.nis});
    if (evidence.size() > settings_.readings) evidence.erase(evidence.begin());
    gathered.insert(t.id);
  }
  for (const LandmarkId id : gathered) {
    auto it = suspects_.find(id);
    if (it == suspects_.end() || !coherent(it->second)) continue;
    double nis = 0;
    for (const auto& e : it->second) nis += e.nis;
    out.moved.emplace_back(id, nis / static_cast<double>(it->second.size()));
    out.held.erase(id);  // this step's reading starts the new landmark
    suspects_.erase(it);
  }
  return out;
}

}  // namespace budget_slam::reducers
