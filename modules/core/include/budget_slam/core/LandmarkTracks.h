#pragma once
#include <Eigen/Core>
#include <map>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"

namespace budget_slam {

/// The sightings of one landmark, as both backends keep them for LandmarkView: how many, the
/// running mean of the robot positions it was seen from (Hochdorfer & Schlegel Eq. 1-2) and the
/// first and last step it was seen at.
struct LandmarkTrack {
  std::size_t n = 0;                                   ///< sightings so far
  Eigen::Vector2d obs_mean = Eigen::Vector2d::Zero();  ///< [m]
  StepIndex first_step = 0, last_step = 0;

  /// One more sighting from the robot position `robot` [m] at `step`: the running mean of
  /// Hochdorfer & Schlegel Eq. 2, obs_mean += (robot - obs_mean) / n.
  void addSighting(const Eigen::Vector2d& robot, StepIndex step) {
    ++n;
    obs_mean += (robot - obs_mean) / static_cast<double>(n);
    last_step = step;
  }
  /// Copies the sighting fields into `v` (n_obs, obs_mean, first_step, last_step).
  void describe(LandmarkView* v) const {
    v->n_obs = n;
    v->obs_mean = obs_mean;
    v->first_step = first_step;
    v->last_step = last_step;
  }
};

/// Every map landmark's LandmarkTrack, by id. A landmark removed from the map loses its track
/// (erase); seen again, it starts a new one.
class LandmarkTracks {
 public:
  /// A sighting of `id` from `robot` [m] at `step`; the first one starts the track at `step`.
  void addSighting(LandmarkId id, const Eigen::Vector2d& robot, StepIndex step) {
    auto [it, is_new] = tracks_.try_emplace(id);
    if (is_new) it->second.first_step = step;
    it->second.addSighting(robot, step);
  }
  void erase(LandmarkId id) { tracks_.erase(id); }
  /// Takes a landmark's record back from its view (a resumed session: LandmarkView carries it).
  void restore(const LandmarkView& v) {
    LandmarkTrack& t = tracks_[v.id];
    t.n = v.n_obs;
    t.obs_mean = v.obs_mean;
    t.first_step = v.first_step;
    t.last_step = v.last_step;
  }
  /// The track of `id`, or nullptr when it has none.
  const LandmarkTrack* find(LandmarkId id) const {
    const auto it = tracks_.find(id);
    return it == tracks_.end() ? nullptr : &it->second;
  }
  /// Throws std::out_of_range when `id` has no track.
  const LandmarkTrack& at(LandmarkId id) const { return tracks_.at(id); }
  /// The landmarks last seen at `step` (Backend::observedAt), sorted by id.
  std::vector<LandmarkId> observedAt(StepIndex step) const {
    std::vector<LandmarkId> out;
    for (const auto& [id, t] : tracks_)  // a std::map: already sorted by id
      if (t.last_step == step && t.n > 0) out.push_back(id);
    return out;
  }

 private:
  std::map<LandmarkId, LandmarkTrack> tracks_;
};

}  // namespace budget_slam
