#pragma once
#include <cstddef>
#include <limits>
#include <vector>

#include "budget_slam/core/Pose2.h"

namespace budget_slam::metrics {

/// Path length between the two poses of an RPE pair [m]: "drift per 10 m travelled".
constexpr double kRpeDeltaMetres = 10.0;

/// The translational relative pose error over every stretch of 10 m of ground-truth path: for
/// each pose i, the stretch ends at the first pose j after i at which the path travelled since i
/// (the ground-truth positions' distances summed from i on) reaches `delta`; poses whose path
/// never reaches it start no stretch. A stretch's error is the length of the translation of
/// (G_i⁻¹ G_j)⁻¹ (E_i⁻¹ E_j), E the estimate and G the ground truth in SE(2): what evo_rpe computes
/// with `--delta 10 --delta_unit m --all_pairs` and its default translation part, except that evo
/// ends a stretch at the pose closest to 10 m (within ±1 m) where this takes the first one at
/// 10 m or more (no stretch shorter than 10 m, and no tie between two poses). It is blind to the
/// frame (a rigid transform of the whole estimate changes nothing), so it measures local drift
/// where the aligned ATE measures the shape as a whole. Every pose starts a stretch (evo's default
/// of consecutive, non-overlapping stretches leaves 3 on a 40 m run).
struct RelativePoseError {
  std::size_t pairs = 0;                                   ///< pairs measured (0: path too short)
  double rmse = std::numeric_limits<double>::quiet_NaN();  ///< [m per `delta` m]
  double max = std::numeric_limits<double>::quiet_NaN();   ///< [m]
};

/// `estimate` and `truth` hold the same poses in the same order (one pair a pose of the
/// trajectory). NaN (0 pairs) when the ground-truth path is shorter than delta.
RelativePoseError relativePoseError(const std::vector<Pose2>& estimate,
                                    const std::vector<Pose2>& truth,
                                    double delta = kRpeDeltaMetres);

}  // namespace budget_slam::metrics
