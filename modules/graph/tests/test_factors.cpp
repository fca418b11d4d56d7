// Analytic Jacobians of every factor against central differences (GTSAM's habit), and the
// composition of odometry factors against the Schur complement of the linearized chain (the pose
// type's own operations are checked in modules/core/tests/test_pose2.cpp).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <functional>
#include <random>

#include "budget_slam/graph/Factors.h"

using namespace budget_slam::graph;

namespace {
/// Central-difference Jacobian of f at x (residual angles wrapped by f itself; differences of
/// wrapped outputs are re-wrapped in `wrap_rows`).
Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, std::vector<int> wrap_rows = {}) {
  const double h = 1e-6;
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    Eigen::VectorXd d = f(xp) - f(xm);
    for (int r : wrap_rows) d[r] = wrapAngle(d[r]);
    J.col(i) = d / (2 * h);
  }
  return J;
}

struct Rng {
  std::mt19937 g{42};
  double u(double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
  Pose2 pose() { return Pose2(u(-5, 5), u(-5, 5), u(-M_PI, M_PI)); }
};
}  // namespace

TEST(Factors, PriorErrorAndJacobian) {
  const PriorFactor f = PriorFactor::make(Pose2(1, 2, 3.1), Eigen::Matrix3d::Identity());
  Eigen::Matrix3d J;
  const Eigen::Vector3d e = f.error(Pose2(1.5, 2, -3.1), &J);
  EXPECT_NEAR(e.x(), 0.5, 1e-15);
  EXPECT_NEAR(e.z(), 2 * M_PI - 6.2, 1e-12);  // wrapped across +-pi
  auto fe = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    return f.error(Pose2(Eigen::Vector3d(v)));
  };
  EXPECT_TRUE(J.isApprox(numericJacobian(fe, Pose2(1.5, 2, -3.1).vector(), {2}), 1e-8));
}

TEST(Factors, BetweenJacobians) {
  Rng r;
  for (int k = 0; k < 20; ++k) {
    const Pose2 xi = r.pose(), xj = r.pose();
    const BetweenFactor f =
        BetweenFactor::make(Pose2(r.pose().vector() * 0.1), Eigen::Matrix3d::Identity());
    Eigen::Matrix3d Ji, Jj;
    f.error(xi, xj, &Ji, &Jj);
    auto fi = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
      return f.error(Pose2(Eigen::Vector3d(v)), xj);
    };
    auto fj = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
      return f.error(xi, Pose2(Eigen::Vector3d(v)));
    };
    EXPECT_TRUE(Ji.isApprox(numericJacobian(fi, xi.vector(), {2}), 1e-7));
    EXPECT_TRUE(Jj.isApprox(numericJacobian(fj, xj.vector(), {2}), 1e-7));
  }
}

TEST(Factors, RangeBearingJacobiansWithSensorOffset) {
  Rng r;
  for (int k = 0; k < 50; ++k) {
    const Pose2 x = r.pose();
    const Eigen::Vector2d l(r.u(-10, 10), r.u(-10, 10));
    const Pose2 sensor(r.u(-1, 1), r.u(-1, 1), r.u(-1, 1));
    const RangeBearingFactor f =
        RangeBearingFactor::make(r.u(1, 5), r.u(-3, 3), sensor, Eigen::Matrix2d::Identity());
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::Matrix2d Jl;
    f.error(x, l, &Jx, &Jl);
    auto fx = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
      return f.error(Pose2(Eigen::Vector3d(v)), l);
    };
    auto fl = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return f.error(x, v); };
    EXPECT_TRUE(Jx.isApprox(numericJacobian(fx, x.vector(), {1}), 1e-6)) << Jx;
    EXPECT_TRUE(Jl.isApprox(numericJacobian(fl, l, {1}), 1e-6)) << Jl;
  }
}

TEST(Factors, RangeBearingGeometryAndWrap) {
  // Robot at (1, 1) facing +y, sensor 0.5 m ahead turned by -pi/2: it looks along +x.
  const Pose2 x(1, 1, M_PI / 2), sensor(0.5, 0, -M_PI / 2);
  const RangeBearingFactor f = RangeBearingFactor::make(0, 0, sensor, Eigen::Matrix2d::Identity());
  const Eigen::Vector2d h = f.predict(x, Eigen::Vector2d(4, 1.5));  // sensor origin (1, 1.5)
  EXPECT_NEAR(h.x(), 3.0, 1e-12);
  EXPECT_NEAR(h.y(), 0.0, 1e-12);
  // A measured bearing of +pi - 0.01 against a predicted -pi + 0.01: residual 0.02, not 2 pi.
  const RangeBearingFactor g =
      RangeBearingFactor::make(3, M_PI - 0.01, sensor, Eigen::Matrix2d::Identity());
  const Eigen::Vector2d behind(1 - 3 * std::cos(0.01), 1.5 - 3 * std::sin(0.01));
  EXPECT_NEAR(g.error(x, behind).y(), 0.02, 1e-9);
  // Initialisation from the first sighting inverts the prediction.
  const RangeBearingFactor s =
      RangeBearingFactor::make(2.5, 0.7, sensor, Eigen::Matrix2d::Identity());
  EXPECT_NEAR(s.error(x, s.landmarkFrom(x)).norm(), 0, 1e-12);
}

TEST(Factors, SqrtInformationWhitens) {
  Eigen::Matrix3d C;
  C << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.01;
  const Eigen::Matrix3d S = sqrtInformation(C);
  EXPECT_TRUE((S.transpose() * S).isApprox(C.inverse(), 1e-12));
  EXPECT_THROW(sqrtInformation(Eigen::Matrix3d(Eigen::Vector3d(1, 0, 1).asDiagonal())),
               std::invalid_argument);
}

// Composing x_i -> x_j -> x_k into x_i -> x_k equals marginalizing x_j in the linearized
// problem: the Schur complement of x_j in the 9x9 information of the two factors equals the
// 6x6 information of the composed factor (linearized where both factors have zero residual).
TEST(Factors, ComposedOdometryEqualsSchurComplement) {
  Rng r;
  for (int k = 0; k < 20; ++k) {
    const Pose2 xi = r.pose();
    const Pose2 z1(r.u(0, 2), r.u(-0.5, 0.5), r.u(-1, 1)),
        z2(r.u(0, 2), r.u(-0.5, 0.5), r.u(-1, 1));
    auto randomCov = [&] {
      Eigen::Matrix3d A = Eigen::Matrix3d::Random() * 0.1;
      return Eigen::Matrix3d(A * A.transpose() + 0.01 * Eigen::Matrix3d::Identity());
    };
    const BetweenFactor f1 = BetweenFactor::make(z1, randomCov()),
                        f2 = BetweenFactor::make(z2, randomCov());
    const Pose2 xj = compose(xi, z1), xk = compose(xj, z2);
    // Chain information over (x_i, x_j, x_k).
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(9, 9);
    Eigen::Matrix3d A, B;
    f1.error(xi, xj, &A, &B);
    Eigen::Matrix<double, 3, 9> J1 = Eigen::Matrix<double, 3, 9>::Zero();
    J1 << A, B, Eigen::Matrix3d::Zero();
    H += J1.transpose() * f1.cov.inverse() * J1;
    f2.error(xj, xk, &A, &B);
    Eigen::Matrix<double, 3, 9> J2;
    J2 << Eigen::Matrix3d::Zero(), A, B;
    H += J2.transpose() * f2.cov.inverse() * J2;
    // Schur complement of x_j onto (x_i, x_k).
    const std::vector<int> keep{0, 1, 2, 6, 7, 8};
    Eigen::MatrixXd Hkk(6, 6), Hkj(6, 3);
    for (int a = 0; a < 6; ++a) {
      for (int b = 0; b < 6; ++b) Hkk(a, b) = H(keep[a], keep[b]);
      for (int b = 0; b < 3; ++b) Hkj(a, b) = H(keep[a], 3 + b);
    }
    const Eigen::MatrixXd schur = Hkk - Hkj * H.block<3, 3>(3, 3).inverse() * Hkj.transpose();
    // Composed factor.
    const BetweenFactor c = composeBetween(f1, f2);
    EXPECT_NEAR(c.error(xi, xk).norm(), 0, 1e-12);
    c.error(xi, xk, &A, &B);
    Eigen::Matrix<double, 3, 6> Jc;
    Jc << A, B;
    const Eigen::MatrixXd Hc = Jc.transpose() * c.cov.inverse() * Jc;
    EXPECT_LT((Hc - schur).norm(), 1e-8 * schur.norm()) << Hc << "\n\n" << schur;
  }
}
