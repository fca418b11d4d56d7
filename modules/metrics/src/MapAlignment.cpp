#include "budget_slam/metrics/MapAlignment.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>

#include "budget_slam/core/MrptPose.h"

namespace budget_slam::metrics {

double MapAlignment::yaw() const { return std::atan2(transform.R(1, 0), transform.R(0, 0)); }

Pose2 MapAlignment::apply(const Pose2& p) const {
  const Eigen::Vector2d q = transform.apply(Eigen::Vector2d(p.x, p.y));
  return {q.x(), q.y(), mrpt::math::wrapToPi(p.phi + yaw())};
}

MapAlignment MapAlignment::fromPose(double x, double y, double yaw, std::string source,
                                    std::size_t points) {
  MapAlignment a;
  a.transform.R << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
  a.transform.t = Eigen::Vector2d(x, y);
  a.source = std::move(source);
  a.points = points;
  return a;
}

std::optional<MapAlignment> mapAlignment(const std::vector<LandmarkView>& landmarks,
                                         const std::vector<TrajectoryPoint>& trajectory,
                                         const dataset::GroundTruth& truth, std::size_t steps) {
  std::vector<Eigen::Vector2d> from, to;
  for (const auto& l : landmarks) {
    const auto it = truth.landmarks.find(l.id);
    if (it == truth.landmarks.end()) continue;
    from.push_back(it->second);
    to.push_back(l.mean);
  }
  // The least-squares rigid fit of the matched points, named for where they came from.
  const auto fitted = [&](const char* source) {
    MapAlignment a;
    a.transform = alignPoints(from, to);
    a.source = source;
    a.points = from.size();
    return a;
  };
  if (from.size() >= 3) return std::optional<MapAlignment>(fitted("landmarks"));
  if (truth.path.empty()) return std::nullopt;
  from.clear(), to.clear();
  for (const auto& p : trajectory) {
    const std::size_t row = groundTruthRow(p.step, truth.path.size(), steps);
    if (row >= truth.path.size()) continue;
    from.emplace_back(truth.path[row].x, truth.path[row].y);
    to.emplace_back(p.pose.x, p.pose.y);
  }
  if (from.size() >= 2) return std::optional<MapAlignment>(fitted("trajectory"));
  // The map's nominal frame: the true start pose is its origin.
  const mrpt::poses::CPose2D inv = -mrpt::poses::CPose2D(toTPose2D(truth.path.front()));
  return MapAlignment::fromPose(inv.x(), inv.y(), inv.phi(), "start_pose", 1);
}

}  // namespace budget_slam::metrics
