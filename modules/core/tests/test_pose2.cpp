// The pose type against numerical Jacobians and its group identities.
#include <gtest/gtest.h>

#include <random>

#include "NumericJacobian.h"
#include "budget_slam/core/Pose2.h"

using namespace budget_slam;
using budget_slam::test::numericJacobian;

namespace {

using Fn3 = std::function<Eigen::VectorXd(const Eigen::Vector3d&)>;
using Fn2 = std::function<Eigen::VectorXd(const Eigen::Vector2d&)>;

double maxAbs(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

std::vector<Pose2> randomPoses(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5, 5), a(-M_PI, M_PI);
  std::vector<Pose2> out;
  for (int k = 0; k < n; ++k) out.emplace_back(u(rng), u(rng), a(rng));
  return out;
}

}  // namespace

TEST(Pose2, WrapAngleIsInRange) {
  EXPECT_NEAR(wrapAngle(3 * M_PI / 2), -M_PI / 2, 1e-15);
  EXPECT_NEAR(wrapAngle(-3 * M_PI / 2), M_PI / 2, 1e-15);
  EXPECT_NEAR(wrapAngle(0.3 + 20 * M_PI), 0.3, 1e-12);
  EXPECT_LE(std::abs(wrapAngle(M_PI)), M_PI);
}

TEST(Pose2, ComposeAndBetweenJacobiansMatchNumerical) {
  const auto poses = randomPoses(40, 7);
  for (size_t k = 0; k + 1 < poses.size(); k += 2) {
    const Pose2 a = poses[k], b = poses[k + 1];
    Eigen::Matrix3d Ja, Jb;
    compose(a, b, &Ja, &Jb);
    EXPECT_LT(maxAbs(Ja, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                              return compose(Pose2(v), b).vector();
                                            }),
                                            a.vector(), {2})),
              1e-7);
    EXPECT_LT(maxAbs(Jb, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                              return compose(a, Pose2(v)).vector();
                                            }),
                                            b.vector(), {2})),
              1e-7);
    between(a, b, &Ja, &Jb);
    EXPECT_LT(maxAbs(Ja, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                              return between(Pose2(v), b).vector();
                                            }),
                                            a.vector(), {2})),
              1e-7);
    EXPECT_LT(maxAbs(Jb, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                              return between(a, Pose2(v)).vector();
                                            }),
                                            b.vector(), {2})),
              1e-7);
  }
}

TEST(Pose2, InverseAndTransformJacobiansMatchNumerical) {
  const auto poses = randomPoses(20, 11);
  const Eigen::Vector2d p(1.7, -0.4);
  for (const Pose2& a : poses) {
    Eigen::Matrix3d J;
    a.inverse(&J);
    EXPECT_LT(maxAbs(J, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                             return Pose2(v).inverse().vector();
                                           }),
                                           a.vector(), {2})),
              1e-7);
    Eigen::Matrix<double, 2, 3> Jpose;
    Eigen::Matrix2d Jpoint;
    a.transformFrom(p, &Jpose, &Jpoint);
    EXPECT_LT(maxAbs(Jpose, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                                 return Pose2(v).transformFrom(p);
                                               }),
                                               a.vector())),
              1e-7);
    EXPECT_LT(
        maxAbs(Jpoint, numericJacobian<2>(
                           Fn2([&](const Eigen::Vector2d& q) { return a.transformFrom(q); }), p)),
        1e-7);
    a.transformTo(p, &Jpose, &Jpoint);
    EXPECT_LT(maxAbs(Jpose, numericJacobian<3>(Fn3([&](const Eigen::Vector3d& v) {
                                                 return Pose2(v).transformTo(p);
                                               }),
                                               a.vector())),
              1e-7);
    EXPECT_LT(
        maxAbs(Jpoint, numericJacobian<2>(
                           Fn2([&](const Eigen::Vector2d& q) { return a.transformTo(q); }), p)),
        1e-7);
  }
}

TEST(Pose2, GroupIdentitiesHold) {
  const auto poses = randomPoses(30, 5);
  for (size_t k = 0; k + 2 < poses.size(); k += 3) {
    const Pose2 a = poses[k], b = poses[k + 1], c = poses[k + 2];
    // a (+) a^-1 is the identity; between(a, b) is a^-1 (+) b; a (+) between(a, b) is b.
    EXPECT_LT(compose(a, a.inverse()).vector().norm(), 1e-12);
    EXPECT_LT(maxAbs(between(a, b).vector(), compose(a.inverse(), b).vector()), 1e-12);
    EXPECT_LT(maxAbs(compose(a, between(a, b)).vector(), b.vector()), 1e-12);
    // Composition is associative.
    Eigen::Vector3d d = compose(compose(a, b), c).vector() - compose(a, compose(b, c)).vector();
    d.z() = wrapAngle(d.z());
    EXPECT_LT(d.norm(), 1e-12);
    // transformTo undoes transformFrom, and both agree with composing a pose at the point.
    const Eigen::Vector2d p(c.x, c.y);
    EXPECT_LT((a.transformTo(a.transformFrom(p)) - p).norm(), 1e-12);
    EXPECT_LT((a.transformFrom(p) - compose(a, c).translation()).norm(), 1e-12);
    EXPECT_LT((a.transformFrom(p) - (a.translation() + a.rotation() * p)).norm(), 1e-12);
  }
}
