#pragma once
// Central differences for checking analytic Jacobians: the core's pose and sensor model tests.
#include <Eigen/Core>
#include <functional>

#include "budget_slam/core/Pose2.h"

namespace budget_slam::test {

/// d f / d x at x by central differences (step 1e-6); the rows in `wrapped` (angles) have their
/// differences wrapped to [-pi, pi].
template <int N>
Eigen::MatrixXd numericJacobian(
    const std::function<Eigen::VectorXd(const Eigen::Matrix<double, N, 1>&)>& f,
    const Eigen::Matrix<double, N, 1>& x, std::initializer_list<int> wrapped = {}) {
  const double h = 1e-6;
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), N);
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> a = x, b = x;
    a(i) += h;
    b(i) -= h;
    Eigen::VectorXd d = f(a) - f(b);
    for (int r : wrapped) d(r) = wrapAngle(d(r));
    J.col(i) = d / (2 * h);
  }
  return J;
}

}  // namespace budget_slam::test
