#pragma once
#include <vector>

#include "budget_slam/core/Estimates.h"
#include "budget_slam/core/Pose2.h"
#include "budget_slam/wakeup/PoseFit.h"
#include "budget_slam/wakeup/ReadingWindow.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace budget_slam::wakeup {

/// How the window fit treats the map's landmarks.
enum class WindowLandmarks {
  Fixed,   ///< at their means: the robot relative to the map as it is drawn
  Priors,  ///< unknowns with their map marginals as priors: the robot in the map's frame
};

/// The window's poses fitted jointly (docs/ALGORITHMS.md "Waking up on a saved map", "Over a
/// window"): the unknowns are the robot pose X_j of every gathered step and, with
/// WindowLandmarks::Priors, each map landmark the pairings name, l_m; the factors are
///   - the odometry between consecutive steps, between(X_{j-1}, X_j) = u_j, covariance Q_j;
///   - each paired reading, z = h(X_j (+) sensor, l_m) (predictRangeBearing), covariance R (the
///     landmark at its map mean when Fixed);
///   - with Priors, each named landmark's prior from the saved map, l_m = mean_m, covariance its
///     marginal.
/// Gauss-Newton from `start` (the latest pose; the earlier ones from the odometry chain, the
/// landmarks at their means), each step halved while it raises the cost. The latest pose X_k is
/// eliminated last: its marginal information is the Schur complement
/// S = H_kk - H_kr H_rr^-1 H_rk of the rest (H_rr is positive definite whenever the odometry
/// covariances are: each earlier pose is tied to X_k through the chain, each landmark by its
/// prior), so an unobserved direction of X_k (the rotation about a single landmark, however often
/// it was read) shows in S alone. Readings of one landmark from several steps share the odometry
/// between them (and, with Priors, that landmark's map error) rather than counting as independent
/// evidence, as the latest-pose fit (refinePose) counts them.
///
/// Returns, as refinePose does: the latest pose, its marginal covariance S^-1 and information S,
/// and each pairing's squared Mahalanobis innovation against the map's landmark mean under its
/// step's fitted pose, with S_i = R + H_l Sigma_l H_l^T. Not converged when S is not positive
/// definite or after `max_iterations`. Odometry and landmark covariances get kCovarianceFloor on
/// their diagonals so that an exact (zero) covariance stays invertible.
Refinement fitWindow(const Pose2& start, const std::vector<WindowStep>& steps,
                     const std::vector<LocalReading>& readings,
                     const std::vector<LandmarkView>& map, const std::vector<Pairing>& pairs,
                     const ReadingNoise& noise, WindowLandmarks landmarks, int max_iterations = 30);

/// Added to the diagonal of every odometry and landmark covariance the window fit inverts
/// [m^2, rad^2]: a 1e-6 m / 1e-6 rad standard deviation, far below any sensor's.
constexpr double kCovarianceFloor = 1e-12;

}  // namespace budget_slam::wakeup
