#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Ids.h"

namespace budget_slam::reducers {

/// What the budget knows of one kept landmark's confirmations (docs/ALGORITHMS.md "Negative
/// evidence"): when it was last observed, and how many passes through its view went by without a
/// sighting since then. Part of what a session saves (BudgetManager::negativeEvidence()).
struct ConfirmationRecord {
  StepIndex last_confirmed_step = 0;  ///< last step the landmark was observed
  std::uint32_t misses = 0;           ///< passes missed since last_confirmed_step
  bool in_pass = false;               ///< expected in view at the last step with readings
  bool counted = false;               ///< this pass has been counted as a miss
  std::uint32_t pass_unseen = 0;      ///< steps of this pass without a sighting
  /// Place cells (NegativeEvidence::cellOf) the landmark was observed from, sorted; at most
  /// Settings::max_viewpoints.
  std::vector<std::int64_t> viewpoints;
};

/// The sensor as the step that is checked states it.
struct SensorView {
  Pose2 pose_on_robot;                  ///< [m, m, rad]
  double min_range = 0, max_range = 0;  ///< [m]
  double fov = 0;                       ///< total horizontal field of view [rad]
};

/// Counts, for every kept landmark, the passes through its view in which it was not observed: a
/// landmark is expected at a step when, from the filter's pose estimate, it lies within the
/// sensor's range and field of view (less margins) and the robot stands in a place cell from
/// which it has been observed before (that cell's view of it is known to be clear: walls and
/// rooms are learned, not assumed). A pass is a run of consecutive steps with readings in which
/// it is expected; a pass counts one miss once it has `min_pass_steps` steps without a sighting.
/// Any sighting confirms the landmark and clears its misses.
class NegativeEvidence {
 public:
  struct Settings {
    std::size_t misses_to_distrust = 2;  ///< K: misses that make a landmark distrusted
    std::size_t min_pass_steps = 2;      ///< unseen steps in view that make a pass a miss
    double viewpoint_cell = 0.5;         ///< side of a place cell [m], > 0
    double range_margin = 0.5;           ///< kept inside [min, max] range [m], >= 0
    double fov_margin = 0.0872664626;    ///< kept inside each edge of the field of view [rad]
    std::size_t max_viewpoints = 256;    ///< cells remembered a landmark
  };

  explicit NegativeEvidence(const Settings& settings) : settings_(settings) {}

  /// After a step with readings: `robot` is the pose estimate, `landmarks` the map, `observed`
  /// the landmarks the step's readings went to, `held` those whose readings were left out as
  /// suspected of having moved (MovedLandmarks): seen, but not where the map has them, so the
  /// step neither confirms them nor counts against them.
  void update(StepIndex step, const Pose2& robot, const SensorView& sensor,
              const std::vector<LandmarkView>& landmarks, const std::vector<LandmarkId>& observed,
              const std::set<LandmarkId>& held = {});

  /// Landmarks with at least K misses: most misses first, then the longest unconfirmed, then id.
  std::vector<LandmarkId> distrusted() const;
  /// True when the landmark at `mean` is within the sensor's view (less margins) from `robot`.
  bool inView(const Pose2& robot, const SensorView& sensor, const Eigen::Vector2d& mean) const;
  /// The cell of a robot position; cells far beyond any map (> 1e9 cells) share one key.
  std::int64_t cellOf(double x, double y) const;

  void forget(LandmarkId id) { records_.erase(id); }
  /// Every record, by landmark id (to save with a session), and back.
  const std::map<LandmarkId, ConfirmationRecord>& records() const { return records_; }
  void restore(std::map<LandmarkId, ConfirmationRecord> records) { records_ = std::move(records); }
  const Settings& settings() const { return settings_; }

 private:
  Settings settings_;
  std::map<LandmarkId, ConfirmationRecord> records_;
};

}  // namespace budget_slam::reducers
