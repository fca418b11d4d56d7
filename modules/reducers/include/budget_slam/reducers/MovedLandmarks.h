#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Step.h"

namespace budget_slam::reducers {

/// One reading of a kept landmark that failed its innovation gate while the rest of the step's
/// view agreed with the map (docs/ALGORITHMS.md "Moved landmarks").
struct MovedEvidence {
  StepIndex step = 0;
  Eigen::Vector2d robot = Eigen::Vector2d::Zero();  ///< predicted robot position [m]
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< where the reading puts the landmark [m]
  Eigen::Matrix2d point_cov = Eigen::Matrix2d::Identity();  ///< of `point` [m^2]
  double nis = 0;  ///< the reading's normalized innovation squared against the old estimate
};

/// What the screening of one step decided.
struct MovedScreening {
  /// Landmarks whose readings of this step must not be fused: under suspicion, evidence
  /// gathering (their readings are left out of the step).
  std::set<LandmarkId> held;
  /// Landmarks recognised as moved at this step, each with the mean NIS of its evidence: the
  /// old estimate must leave the map before the step is fused, so that the step's reading
  /// starts a new landmark.
  std::vector<std::pair<LandmarkId, double>> moved;
};

/// Recognises a kept landmark that has moved (docs/ALGORITHMS.md "Moved landmarks"). Before a
/// step is fused, each reading of a landmark of the map (by its sensor ID) is tested against the
/// landmark's estimate from the robot pose predicted with the step's odometry: the normalized
/// innovation squared d² = νᵀ S⁻¹ ν, S the innovation covariance from the joint covariance of
/// the robot and the landmark (Bar-Shalom's gate). A reading outside the gate is evidence of a
/// move only when the rest of the view agrees with the map: at least `min_agreeing` other
/// landmarks read in the same step pass their gates and outnumber those that fail (a pose error
/// moves every innovation together; a moved landmark moves one). A landmark with evidence is
/// suspect: its readings are held (not fused) until either a reading passes its gate again (the
/// suspicion is cleared) or `readings` pieces of evidence from places at least `place_distance`
/// apart put it at one new place (each point within the gate of their mean): then it has moved.
class MovedLandmarks {
 public:
  struct Settings {
    double gate_chi2 = 13.8155;    ///< innovation gate, chi-square 2 dof (99.9%)
    std::size_t readings = 3;      ///< evidence from distinct places that splits [readings]
    double place_distance = 0.5;   ///< robot positions of two pieces of evidence at least [m]
    std::size_t min_agreeing = 2;  ///< other landmarks of the step that must pass their gates
    double std_range = 0.1;        ///< reading noise, 1 sigma [m]
    double std_bearing = 0.5 * M_PI / 180;  ///< reading noise, 1 sigma [rad]
    std::size_t max_suspects = 4096;        ///< landmarks under suspicion at most
  };

  explicit MovedLandmarks(const Settings& settings) : settings_(settings) {}

  /// Tests the readings of `step` (with sensor IDs) against `backend`'s map as it stands before
  /// the step is fused; `last_step` is the step of the backend's latest pose when known (its
  /// joint covariance with the landmarks is then used; without it, their marginals). Updates
  /// the evidence and returns what to hold and what has moved.
  MovedScreening screen(const Backend& backend, const Step& step,
                        std::optional<StepIndex> last_step);

  /// The landmark left the map (dropped, or split as moved): its evidence goes.
  void forget(LandmarkId id) { suspects_.erase(id); }
  /// The evidence of every suspect landmark, by id (to save with a session), and back.
  const std::map<LandmarkId, std::vector<MovedEvidence>>& suspects() const { return suspects_; }
  void restore(std::map<LandmarkId, std::vector<MovedEvidence>> s) { suspects_ = std::move(s); }
  const Settings& settings() const { return settings_; }
  void setReadingNoise(double std_range, double std_bearing) {
    settings_.std_range = std_range;
    settings_.std_bearing = std_bearing;
  }

 private:
  Settings settings_;
  std::map<LandmarkId, std::vector<MovedEvidence>> suspects_;

  /// True when the evidence points agree on one place; drops the oldest pieces until they do.
  bool coherent(std::vector<MovedEvidence>& evidence) const;
};

}  // namespace budget_slam::reducers
