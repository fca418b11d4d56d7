#pragma once
#include <Eigen/Core>

namespace budget_slam::reducers {

/// Dissanayake's information content of a landmark, I = 1/sigma_xx^2 + 1/sigma_yy^2 from its
/// marginal covariance (Hochdorfer & Schlegel Eq. 3-4) [1/m^2]. Ignores correlations.
inline double informationContent(const Eigen::Matrix2d& cov) {
  return 1.0 / cov(0, 0) + 1.0 / cov(1, 1);
}

}  // namespace budget_slam::reducers
