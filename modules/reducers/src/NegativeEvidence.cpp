#include "budget_slam/reducers/NegativeEvidence.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace budget_slam::reducers {

std::int64_t NegativeEvidence::cellOf(double x, double y) const {
  const auto index = [&](double v) -> std::int64_t {
    const double c = std::floor(v / settings_.viewpoint_cell);
    if (!(std::abs(c) < 1e9)) return 1000000000;  // NaN or far away: one shared cell
    return static_cast<std::int64_t>(c);
  };
  return index(x) * 4000000001LL + index(y);
}

bool NegativeEvidence::inView(const Pose2& robot, const SensorView& sensor,
                              const Eigen::Vector2d& mean) const {
  const double c = std::cos(robot.phi), s = std::sin(robot.phi);
  const auto& p = sensor.pose_on_robot;
  const Eigen::Vector2d at(robot.x + c * p.x - s * p.y, robot.y + s * p.x + c * p.y);
  const Eigen::Vector2d d = mean - at;
  const double range = d.norm();
  if (!(range >= sensor.min_range + settings_.range_margin &&
        range <= sensor.max_range - settings_.range_margin))
    return false;
  if (sensor.fov >= 2 * M_PI - 1e-9) return true;
  const double bearing = mrpt::math::wrapToPi(std::atan2(d.y(), d.x()) - robot.phi - p.phi);
  return std::abs(bearing) <= sensor.fov / 2 - settings_.fov_margin;
}

void NegativeEvidence::update(StepIndex step, const Pose2& robot, const SensorView& sensor,
                              const std::vector<LandmarkView>& landmarks,
                              const std::vector<LandmarkId>& observed,
                              const std::set<LandmarkId>& held) {
  const std::set<LandmarkId> seen(observed.begin(), observed.end());
  const std::int64_t cell = cellOf(robot.x, robot.y);
  std::map<LandmarkId, ConfirmationRecord> kept;  // records of landmarks still in the map
  for (const LandmarkView& l : landmarks) {
    auto it = records_.find(l.id);
    ConfirmationRecord r;
    if (it != records_.end()) {
      r = std::move(it->second);
    } else {
      r.last_confirmed_step = l.last_step;  // a landmark new to the record: its last sighting
    }
    if (held.count(l.id)) {
      kept.emplace(l.id, std::move(r));
      continue;
    }
    const bool sighted = seen.count(l.id) > 0;
    auto at = std::lower_bound(r.viewpoints.begin(), r.viewpoints.end(), cell);
    const bool known_place = at != r.viewpoints.end() && *at == cell;
    if (sighted) {
      r.last_confirmed_step = step;
      r.misses = 0;
      if (!known_place && r.viewpoints.size() < settings_.max_viewpoints)
        r.viewpoints.insert(at, cell);
    }
    const bool expected = sighted || (known_place && inView(robot, sensor, l.mean));
    if (!expected) {
      r.in_pass = false;
    } else {
      if (!r.in_pass) r.in_pass = true, r.counted = false, r.pass_unseen = 0;
      if (sighted) {
        r.counted = true;  // this pass saw it: no miss from it
      } else if (!r.counted && ++r.pass_unseen >= settings_.min_pass_steps) {
        r.counted = true;
        r.misses++;
      }
    }
    kept.emplace(l.id, std::move(r));
  }
  records_ = std::move(kept);
}

std::vector<LandmarkId> NegativeEvidence::distrusted() const {
  std::vector<std::pair<LandmarkId, const ConfirmationRecord*>> out;
  for (const auto& [id, r] : records_)
    if (r.misses >= settings_.misses_to_distrust) out.emplace_back(id, &r);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    if (a.second->misses != b.second->misses) return a.second->misses > b.second->misses;
    if (a.second->last_confirmed_step != b.second->last_confirmed_step)
      return a.second->last_confirmed_step < b.second->last_confirmed_step;
    return a.first < b.first;
  });
  std::vector<LandmarkId> ids;
  for (const auto& [id, r] : out) ids.push_back(id);
  return ids;
}

}  // namespace budget_slam::reducers
