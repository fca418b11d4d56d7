#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "budget_slam/core/RangeBearingModel.h"

using namespace budget_slam;

namespace {

/// Central differences of the predicted reading with respect to the robot pose (3 columns) and
/// the landmark (2 columns).
Eigen::Matrix<double, 2, 5> numericalJacobian(const mrpt::math::TPose2D& robot,
                                              const mrpt::math::TPose2D& sensor,
                                              const Eigen::Vector2d& landmark) {
  Eigen::Matrix<double, 2, 5> J;
  const double h = 1e-6;
  for (int k = 0; k < 5; ++k) {
    mrpt::math::TPose2D rp = robot, rm = robot;
    Eigen::Vector2d lp = landmark, lm = landmark;
    if (k < 3) {
      (k == 0 ? rp.x : k == 1 ? rp.y : rp.phi) += h;
      (k == 0 ? rm.x : k == 1 ? rm.y : rm.phi) -= h;
    } else {
      lp(k - 3) += h;
      lm(k - 3) -= h;
    }
    Eigen::Vector2d d =
        predictRangeBearing(rp, sensor, lp).z - predictRangeBearing(rm, sensor, lm).z;
    d(1) = std::remainder(d(1), 2 * M_PI);
    J.col(k) = d / (2 * h);
  }
  return J;
}

}  // namespace

TEST(RangeBearingModel, JacobiansEqualNumericalOnes) {
  const mrpt::math::TPose2D sensor(0.3, -0.1, 0.2);  // an offset and a yaw on the robot
  for (const auto& [robot, landmark] :
       {std::pair{mrpt::math::TPose2D(1, 2, 0.3), Eigen::Vector2d(4, 5)},
        std::pair{mrpt::math::TPose2D(-3, 0.5, 2.9), Eigen::Vector2d(-6, 1)},
        std::pair{mrpt::math::TPose2D(0, 0, -1.2), Eigen::Vector2d(0.5, -2)}}) {
    const auto p = predictRangeBearing(robot, sensor, landmark);
    const auto J = numericalJacobian(robot, sensor, landmark);
    EXPECT_LT((p.H_robot - J.leftCols<3>()).cwiseAbs().maxCoeff(), 1e-7);
    EXPECT_LT((p.H_landmark - J.rightCols<2>()).cwiseAbs().maxCoeff(), 1e-7);
    // The reading read back puts the landmark where it is.
    const Eigen::Vector2d q = readingInRobotFrame(p.z(0), p.z(1), sensor);
    const double c = std::cos(robot.phi), s = std::sin(robot.phi);
    EXPECT_NEAR(robot.x + c * q.x() - s * q.y(), landmark.x(), 1e-12);
    EXPECT_NEAR(robot.y + s * q.x() + c * q.y(), landmark.y(), 1e-12);
  }
}

TEST(RangeBearingModel, OneReadingInformsTwoOfThreeDirections) {
  const auto p = predictRangeBearing({0, 0, 0}, {0, 0, 0}, Eigen::Vector2d(3, 4));
  const Eigen::Matrix3d I = readingInformation(p.H_robot, 0.1, 0.01);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  EXPECT_LT(std::abs(eig.eigenvalues()(0)), 1e-9 * eig.eigenvalues()(2));
  EXPECT_GT(eig.eigenvalues()(1), 1.0);
  // The unobserved direction: the robot turning about the landmark (moving on the circle around
  // it while turning by the same angle keeps range and bearing).
  const Eigen::Vector3d about(4, -3, 1);  // d(position)/d(angle) = (ly, -lx), d(yaw) = 1
  EXPECT_LT((I * about).norm(), 1e-9 * I.norm());
}
