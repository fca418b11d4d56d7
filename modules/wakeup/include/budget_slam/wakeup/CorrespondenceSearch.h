#pragma once
#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <unordered_map>
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/wakeup/ReadingWindow.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

/// Readings of the gathered steps that show one landmark, merged: a tree seen at every step is
/// one piece of evidence, not ten.
struct LocalLandmark {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< latest robot frame [m]
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();    ///< [m^2]
  std::vector<std::size_t> readings;                ///< indices into the readings
};

/// Greedy merge in reading order: a reading joins the first local landmark within `merge_chi2`
/// (squared Mahalanobis distance, both covariances summed), whose point becomes the
/// information-weighted mean; otherwise it starts a new one.
std::vector<LocalLandmark> mergeReadings(const std::vector<LocalReading>& readings,
                                         double merge_chi2);

/// The saved map as the search reads it: the landmarks on a grid for gated nearest-neighbour
/// look-ups, and every pair of landmarks up to a distance, sorted by their distance.
class MapIndex {
 public:
  explicit MapIndex(const std::vector<LandmarkView>& map);

  const std::vector<LandmarkView>& map() const { return map_; }
  /// The largest variance of any landmark's marginal along any direction [m^2].
  double maxVariance() const { return max_var_; }

  /// The map landmark nearest (squared Mahalanobis, `cov` plus the landmark's marginal) to a
  /// point with covariance `cov`, within `gate_chi2`; its index and distance, or none.
  std::optional<std::pair<std::size_t, double>> nearest(const Eigen::Vector2d& point,
                                                        const Eigen::Matrix2d& cov,
                                                        double gate_chi2) const;
  /// Calls f(index) for every landmark within `radius` [m] of `point` (and perhaps a few more:
  /// the caller checks).
  void forEachNear(const Eigen::Vector2d& point, double radius,
                   const std::function<void(std::size_t)>& f) const;

  struct Pair {
    double distance = 0;  ///< [m]
    std::uint32_t a = 0, b = 0;
    double var = 0;  ///< variance of the distance from the two marginals [m^2]
  };
  /// Every pair of landmarks at most `max_distance` apart, by distance (built on first use and
  /// again when a longer distance is asked).
  const std::vector<Pair>& pairsUpTo(double max_distance) const;

 private:
  std::vector<LandmarkView> map_;
  double cell_ = 1;
  double max_var_ = 0;  ///< the largest variance of any landmark along any direction [m^2]
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid_;
  mutable std::vector<Pair> pairs_;
  mutable double pairs_up_to_ = -1;
  std::int64_t key(long cx, long cy) const;
};

/// One pose the search considered: the pose of the latest robot frame in the map, the local
/// landmarks that agree with it, and the map landmarks it says were in view but no reading shows.
struct Hypothesis {
  Pose2 pose;
  std::size_t landmarks = 0;  ///< distinct map landmarks agreeing (one local landmark each)
  double chi2 = 0;            ///< sum of the agreeing squared Mahalanobis distances
  std::size_t missed = 0;     ///< map landmarks well in view at a gathered step, agreeing with none
  /// landmarks - [WakeUp] miss_weight x missed: what the search ranks by.
  double score = 0;
  /// (local landmark, map landmark) of each agreement, by local landmark.
  std::vector<std::pair<std::size_t, std::size_t>> matches;
};

struct SearchOutcome {
  std::optional<Hypothesis> best;  ///< highest score, then least chi2
  /// The best rival: a pose beyond [WakeUp] distinct_xy / distinct_yaw_deg from best's that
  /// shares at most one (local, map) pairing with it.
  std::optional<Hypothesis> runner_up;
  std::size_t hypotheses = 0;  ///< hypotheses scored
  /// More than kMaxPlacesScored places could rival the best: the wake-up is ambiguous.
  bool crowded = false;
};

/// Places scored in full (with negative evidence) at most, an attempt.
constexpr std::size_t kMaxPlacesScored = 256;

/// A map landmark is well in view of a sensor when its range is within [min_range, 0.9 x
/// max_range] and its bearing at least 5 deg inside the field of view: there a landmark that
/// exists is read (the margins keep landmarks at the edge, read or not by chance, out).
constexpr double kInViewRangeShare = 0.9;
constexpr double kInViewAngleMargin = 5 * M_PI / 180;

/// The agreement of every local landmark with the map under `pose` (one map landmark each; a map
/// landmark claimed twice goes to the closer local one), and with `views` (the gathered steps'
/// sensors, may be empty) the map landmarks well in view of one of them that agree with none.
Hypothesis scorePose(const Pose2& pose, const std::vector<LocalLandmark>& local,
                     const MapIndex& index, const std::vector<SensorView>& views,
                     const WakeUpOptions& options);

/// Hypotheses over correspondences (docs/ALGORITHMS.md "Waking up on a saved map"): every pair of
/// local landmarks at least [WakeUp] min_pair_distance apart against every pair of map landmarks
/// whose distance agrees with theirs (within the gate, both marginals counted), each matched both
/// ways round; the two-point rigid fit of each is counted the landmarks that agree with it. When
/// there are more than max_hypotheses, that many are drawn at random (`rng`). The poses with the
/// most agreement, one a place (distinct_xy, distinct_yaw_deg), are then scored in full
/// (scorePose with `views`), until no further pose could come within ambiguity_margin of the best
/// (at most kMaxPlacesScored places; beyond, `crowded`). When no pose is agreed by
/// search_min_landmarks, only the best counted one is returned.
SearchOutcome searchPose(const std::vector<LocalLandmark>& local, const MapIndex& index,
                         const std::vector<SensorView>& views, const WakeUpOptions& options,
                         std::mt19937_64& rng);

}  // namespace budget_slam::wakeup
