// The range-bearing sensor model against numerical Jacobians, its inverse and its information.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "NumericJacobian.h"
#include "budget_slam/core/RangeBearingModel.h"

using namespace budget_slam;
using budget_slam::test::numericJacobian;

namespace {
using Fn3 = std::function<Eigen::VectorXd(const Eigen::Vector3d&)>;
using Fn2 = std::function<Eigen::VectorXd(const Eigen::Vector2d&)>;
}  // namespace

TEST(RangeBearingModel, JacobiansEqualNumericalOnes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5), a(-M_PI, M_PI);
  int checked = 0;
  for (int trial = 0; trial < 50; ++trial) {
    // A sensor with an offset and a heading on the robot.
    const Pose2 robot(u(rng), u(rng), a(rng)), sensor(0.3 * u(rng) / 5, 0.2 * u(rng) / 5, a(rng));
    const Eigen::Vector2d lm(u(rng) * 3, u(rng) * 3);
    if ((lm - compose(robot, sensor).translation()).norm() < 0.5) continue;
    ++checked;
    const auto p = predictRangeBearing(robot, sensor, lm);
    const auto Jr = numericJacobian<3>(
        Fn3([&](const Eigen::Vector3d& x) { return predictRangeBearing(Pose2(x), sensor, lm).z; }),
        robot.vector(), {1});
    const auto Js = numericJacobian<3>(
        Fn3([&](const Eigen::Vector3d& x) { return predictRangeBearing(robot, Pose2(x), lm).z; }),
        sensor.vector(), {1});
    const auto Jl = numericJacobian<2>(
        Fn2([&](const Eigen::Vector2d& x) { return predictRangeBearing(robot, sensor, x).z; }), lm,
        {1});
    EXPECT_LT((p.H_robot - Jr).cwiseAbs().maxCoeff(), 1e-6) << trial;
    EXPECT_LT((p.H_sensor - Js).cwiseAbs().maxCoeff(), 1e-6) << trial;
    EXPECT_LT((p.H_landmark - Jl).cwiseAbs().maxCoeff(), 1e-6) << trial;
    // The prediction is the reading the landmark gives: readingPoint inverts it, in the world
    // (the sensor's pose in the world) and in the robot frame (its pose on the robot).
    EXPECT_LT((readingPoint(p.z.x(), p.z.y(), compose(robot, sensor)) - lm).norm(), 1e-9);
    EXPECT_LT((robot.transformFrom(readingPoint(p.z.x(), p.z.y(), sensor)) - lm).norm(), 1e-9);
    EXPECT_LE(std::abs(p.z.y()), M_PI);
  }
  EXPECT_GT(checked, 40);
}

TEST(RangeBearingModel, ReadingPointJacobiansMatchNumerical) {
  const Pose2 sensor(0.4, -0.2, 0.9);
  const double range = 6.5, bearing = -0.7;
  Eigen::Matrix<double, 2, 3> Js;
  Eigen::Matrix2d Jz;
  readingPoint(range, bearing, sensor, &Js, &Jz);
  const auto ns = numericJacobian<3>(
      Fn3([&](const Eigen::Vector3d& x) { return readingPoint(range, bearing, Pose2(x)); }),
      sensor.vector());
  const auto nz = numericJacobian<2>(
      Fn2([&](const Eigen::Vector2d& z) { return readingPoint(z.x(), z.y(), sensor); }),
      Eigen::Vector2d(range, bearing));
  EXPECT_LT((Js - ns).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((Jz - nz).cwiseAbs().maxCoeff(), 1e-7);
}

TEST(RangeBearingModel, OneReadingInformsTwoOfThreeDirections) {
  const auto p = predictRangeBearing({0, 0, 0}, {0, 0, 0}, Eigen::Vector2d(3, 4));
  const Eigen::Matrix3d I = readingInformation(p.H_robot, 0.1, 0.01);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  EXPECT_LT(std::abs(eig.eigenvalues()(0)), 1e-9 * eig.eigenvalues()(2));
  EXPECT_GT(eig.eigenvalues()(1), 1.0);
  // The unobserved direction: the robot turning about the landmark (moving on the circle around
  // it while turning by the same angle keeps range and bearing).
  const Eigen::Vector3d about(4, -3, 1);  // d(position)/d(angle) = (ly, -lx), d(phi) = 1
  EXPECT_LT((I * about).norm(), 1e-9 * I.norm());
}
