#pragma once
#include <limits>
#include <vector>

#include "budget_slam/core/Backend.h"

namespace budget_slam::metrics {

/// A reduced run against the unreduced reference run of the same backend and rawlog, over the
/// poses and landmarks the reduced run kept (Choudhary et al. Sec. V-B, Eq. 8-12). SI units except
/// where named.
struct ReferenceMetrics {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t poses = 0;      ///< poses compared (matched by step)
  std::size_t landmarks = 0;  ///< landmarks compared (matched by id)
  double ate = kNaN;          ///< RMSE of position differences [m] (Eq. 8)
  double ale = kNaN;          ///< RMSE of landmark position differences [m] (Eq. 9)
  double are_deg = kNaN;      ///< mean absolute heading difference [deg] (Eq. 10)
  double ud_percent = kNaN;   ///< % increase of det of the latest pose covariance (Eq. 12)
  /// UD as a factor on standard deviations: (det_reduced / det_reference)^(1/6), the geometric
  /// mean of the growth of the 3x3 pose covariance's standard deviations (UD = 7.6e6 % is 6.5x).
  double ud_std_factor = kNaN;
  /// Eigenvalue range of Sigma_ref - Sigma_reduced over the kept variables (Eq. 11; Carlevaris-
  /// Bianco et al.'s eigen envelope): all <= 0 when the reduced run is conservative (as uncertain
  /// as the reference or more in every direction); a positive eig_max is a direction in which it
  /// is more certain. NaN when skipped (more than `eig_max_rows` rows).
  double eig_min = kNaN, eig_max = kNaN;
  std::size_t eig_rows = 0;  ///< size of the compared covariance, 0 if skipped
};

/// Trajectory and landmark metrics from the two estimates. Non-finite estimates are an Error.
ReferenceMetrics compareTrajectories(const std::vector<TrajectoryPoint>& reference,
                                     const std::vector<TrajectoryPoint>& reduced,
                                     const std::vector<LandmarkView>& reference_landmarks,
                                     const std::vector<LandmarkView>& reduced_landmarks);

/// All metrics, including UD and EIG from the backends' covariances. EIG is computed over the
/// latest pose (every kept pose for backends that keep past poses, up to the size limit) and the
/// kept landmarks, and skipped when that covariance would exceed `eig_max_rows` rows, or when a
/// stop request (core/Cancellation.h) comes before or while it is computed: the caller, which
/// sees the request, ends the run as interrupted.
ReferenceMetrics compareWithReference(const Backend& reference, const Backend& reduced,
                                      std::size_t eig_max_rows);

}  // namespace budget_slam::metrics
