#pragma once
#include <cstddef>
#include <cstdint>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::wakeup {

/// How readings are paired with the map's landmarks.
enum class Correspondence {
  Auto,    ///< by id when every reading of the window carries one, else search
  Ids,     ///< by the sensor's landmark id (readings without one are left out)
  Search,  ///< hypotheses over pairs of readings and pairs of landmarks (ids ignored)
};
const EnumNames<Correspondence>& correspondenceNames();

/// What the paired readings of the window are fitted to (docs/ALGORITHMS.md "Waking up on a saved
/// map", "Over a window").
enum class WindowFitMode {
  Window,        ///< every gathered step's pose, the landmarks at their means (fitWindow)
  WindowPriors,  ///< every gathered step's pose and the named landmarks, their marginals as priors
  Latest,        ///< the latest pose alone, the odometry folded into each reading (refinePose)
};
const EnumNames<WindowFitMode>& windowFitModeNames();

/// [WakeUp]: finding the robot on a saved map from the readings of its first steps, with no start
/// pose (docs/ALGORITHMS.md "Waking up on a saved map").
struct WakeUpOptions : public TabledOptions<WakeUpOptions> {
  static constexpr const char* kSection = "WakeUp";

  /// Steps whose readings are gathered before the robot is declared not found [steps]. Default: 10
  std::size_t max_steps = 10;
  /// auto, ids or search. Default: auto
  Correspondence correspondence = Correspondence::Auto;
  /// Distinct map landmarks that must agree with a pose found by id (two range-bearing readings fix
  /// a 2D pose) [landmarks]. Default: 2
  std::size_t min_landmarks = 2;
  /// Distinct map landmarks that must agree with a pose found by search, where any two readings
  /// match many pairs of landmarks [landmarks]. Default: 4
  std::size_t search_min_landmarks = 4;
  /// A reading agrees with a landmark when its squared Mahalanobis innovation is at most this
  /// (chi-square, 2 degrees of freedom; 9.21: 99%). Default: 9.21
  double gate_chi2 = 9.21;
  /// Search: the best pose must be agreed by at least this many landmarks more than the best pose
  /// that differs from it; otherwise the wake-up is ambiguous [landmarks]. Default: 3 (2 let
  /// chance agreements through on Victoria Park's wide gates: docs/RESULTS.md)
  std::size_t ambiguity_margin = 3;
  /// Search: two poses are the same hypothesis when within this distance and this angle
  /// [m], [deg]. Default: 1, 10
  double distinct_xy = 1.0;
  double distinct_yaw_deg = 10.0;
  /// Search: what a map landmark well in view at a gathered step that no reading shows costs a
  /// hypothesis, against 1 for each landmark that agrees (negative evidence; 0: none).
  /// Default: 0.5
  double miss_weight = 0.5;
  /// Search: readings of the gathered steps closer than this (squared Mahalanobis distance) are
  /// one landmark seen again. Default: 9.21
  double merge_chi2 = 9.21;
  /// Search: pairs of readings closer than this give no hypothesis (their angle is poorly
  /// known) [m]. Default: 1
  double min_pair_distance = 1.0;
  /// Search: at most this many hypotheses an attempt; above it, pairs of readings are drawn at
  /// random (seeded) [hypotheses]. Default: 200000
  std::size_t max_hypotheses = 200000;
  std::uint64_t seed = 1;  ///< random draws when max_hypotheses cuts the search. Default: 1
  /// A pose is found only when its standard deviation is at most this: 1 sigma [m], [deg].
  /// Default: 0.25, 5 (the thresholds of "found")
  double max_std_xy = 0.25;
  double max_std_yaw_deg = 5.0;
  /// After the outliers are dropped: window, the poses of every gathered step fitted jointly with
  /// the odometry between them, the landmarks held at their map means (the robot relative to the
  /// map as drawn); window_priors, the landmarks the readings name fitted too, their map marginals
  /// as priors (the robot in the map's frame); latest, the latest pose alone, each reading's sensor
  /// pose carried to it by the odometry (readings counted as independent). Default: window
  WindowFitMode fit = WindowFitMode::Window;
  /// Odometry noise of a step without odometry (zero motion assumed), 1 sigma [m], [deg].
  /// Default: 0.1, 5
  double no_odometry_std_xy = 0.1;
  double no_odometry_std_yaw_deg = 5.0;

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<WakeUpOptions>& table();
};

/// The sensor's reading noise, 1 sigma (from [RangeBearingKFSLAM] std_sensor_range and
/// std_sensor_yaw_deg, as the backends read it).
struct ReadingNoise {
  double std_range = 0.1;     ///< [m]
  double std_bearing = 0.01;  ///< [rad]
};

}  // namespace budget_slam::wakeup
