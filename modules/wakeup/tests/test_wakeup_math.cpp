// The wake-up's math against numerical references: the odometry chain's covariance, the
// closed-form rigid fit and the Gauss-Newton refinement with its covariance (the range-bearing
// model's Jacobians are checked with the model, modules/core/tests/test_range_bearing_model.cpp).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <functional>

#include "NumericJacobian.h"
#include "WakeUpTestUtil.h"
#include "budget_slam/core/RangeBearingModel.h"
#include "budget_slam/wakeup/PoseFit.h"
#include "budget_slam/wakeup/ReadingWindow.h"

using namespace budget_slam;
using namespace budget_slam::wakeup;
using namespace budget_slam::wakeup::test;
using budget_slam::test::numericJacobian;

TEST(WakeUpMath, OdometryChainCovarianceMatchesNumericalPropagation) {
  // Four steps; a landmark read at the first one. Its sensor pose in the last step's frame is a
  // function of the three odometry increments; its covariance must be J diag(Sigma_u) J^T.
  std::vector<Step> steps(4);
  const std::vector<Pose2> u = {Pose2(0.5, 0.1, 0.2), Pose2(0.7, -0.05, -0.3),
                                Pose2(0.4, 0.2, 0.5)};
  const std::vector<Eigen::Matrix3d> cov = {Eigen::Vector3d(0.01, 0.02, 0.003).asDiagonal(),
                                            Eigen::Vector3d(0.02, 0.01, 0.001).asDiagonal(),
                                            Eigen::Vector3d(0.015, 0.005, 0.002).asDiagonal()};
  const Pose2 on_robot(0.3, 0.1, 0.05);
  for (std::size_t k = 0; k < 4; ++k) {
    steps[k].index = 10 + k;
    if (k > 0) {
      OdometryIncrement o;
      o.mean = u[k - 1];
      o.cov = cov[k - 1];
      steps[k].odometry = o;
    }
    RangeBearingScan scan;
    scan.sensor_pose_on_robot = mrpt::math::TPose3D(on_robot.x, on_robot.y, 0, on_robot.phi, 0, 0);
    if (k == 0) scan.readings.push_back({5, 4.0, 0.3, 0});
    steps[k].scan = scan;
  }
  ReadingWindow w({0.1, 0.01}, WakeUpOptions{});
  for (const auto& s : steps) w.add(s);
  const auto r = w.readings();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].step, 10u);
  // The sensor of step 0 in the frame of step 3: (u1 (+) u2 (+) u3)^-1 (+) on_robot.
  const auto sensorOf = [&](const Eigen::Matrix<double, 9, 1>& x) -> Eigen::VectorXd {
    Pose2 p;
    for (int k = 0; k < 3; ++k) p = compose(p, Pose2(x.segment<3>(3 * k)));
    return compose(p.inverse(), on_robot).vector();
  };
  Eigen::Matrix<double, 9, 1> x;
  x << u[0].vector(), u[1].vector(), u[2].vector();
  const Eigen::Vector3d expected = sensorOf(x);
  EXPECT_LT((r[0].sensor.vector() - expected).norm(), 1e-12);
  const auto J = numericJacobian<9>(sensorOf, x);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(9, 9);
  for (int k = 0; k < 3; ++k) S.block<3, 3>(3 * k, 3 * k) = cov[k];
  const Eigen::MatrixXd expected_cov = J * S * J.transpose();
  EXPECT_LT((r[0].sensor_cov - expected_cov).cwiseAbs().maxCoeff(), 1e-8);
  // The point: sensor pose and reading noise propagated.
  Eigen::Matrix<double, 2, 3> Js;
  Eigen::Matrix2d Jz;
  readingPoint(4.0, 0.3, r[0].sensor, &Js, &Jz);
  const Eigen::Matrix2d Rn = Eigen::Vector2d(0.01, 0.0001).asDiagonal();
  EXPECT_LT((r[0].point_cov - (Js * expected_cov * Js.transpose() + Jz * Rn * Jz.transpose()))
                .cwiseAbs()
                .maxCoeff(),
            1e-8);
}

TEST(WakeUpMath, RigidFitRecoversAKnownMotionExactly) {
  const Pose2 T(3.0, -2.0, 2.5);
  std::vector<Eigen::Vector2d> local = {{1, 0}, {0, 2}, {-3, 1}, {4, 4}}, map;
  for (const auto& p : local) map.push_back(T.transformFrom(p));
  const auto fit = fitRigid(local, map, {1, 2, 0.5, 1});
  ASSERT_TRUE(fit.has_value());
  EXPECT_LT((fit->vector() - T.vector()).norm(), 1e-12);
  // Two points fix it too; one does not.
  EXPECT_LT(
      (fitRigid({local[0], local[1]}, {map[0], map[1]}, {1, 1})->vector() - T.vector()).norm(),
      1e-12);
  EXPECT_FALSE(fitRigid({local[0]}, {map[0]}, {1}).has_value());
  EXPECT_FALSE(fitRigid({local[0], local[0]}, {map[0], map[1]}, {1, 1}).has_value());
}

TEST(WakeUpMath, RefinementConvergesAndItsCovarianceIsTheInverseInformation) {
  const std::vector<WorldLandmark> world = {{1, {4, 1}}, {2, {2, 5}}, {3, {-3, 3}}, {4, {6, -4}}};
  const auto map = mapOf(world, 0.05);
  const Pose2 truth(0.5, -0.4, 0.3);
  SensorSetup sensor;
  sensor.on_robot = Pose2(0.2, 0, 0);
  std::mt19937 rng(1);
  const auto steps = stepsAlong({truth}, world, sensor, rng);
  ReadingWindow w({0.1, 0.01}, WakeUpOptions{});
  w.add(steps[0]);
  const auto readings = w.readings();
  std::vector<Pairing> pairs;
  for (std::size_t i = 0; i < readings.size(); ++i) pairs.push_back({i, i});
  const Refinement ref = refinePose(Pose2(truth.vector() + Eigen::Vector3d(0.4, -0.3, 0.15)),
                                    readings, map, pairs, {0.1, 0.01});
  ASSERT_TRUE(ref.converged);
  EXPECT_LT((ref.pose.vector() - truth.vector()).norm(), 1e-9);  // noise-free readings
  for (const double c : ref.chi2) EXPECT_LT(c, 1e-12);
  // Covariance: (sum J^T S^-1 J)^-1 with numerical J and S = R + H_l Sigma_l H_l^T.
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  for (const auto& p : pairs) {
    const auto f = [&](const Eigen::Vector3d& x) -> Eigen::VectorXd {
      return predictRangeBearing(Pose2(x), readings[p.reading].sensor, map[p.landmark].mean).z;
    };
    const Eigen::MatrixXd J = numericJacobian<3>(f, truth.vector(), {1});
    const auto Jl = numericJacobian<2>(
        [&](const Eigen::Vector2d& l) -> Eigen::VectorXd {
          return predictRangeBearing(truth, readings[p.reading].sensor, l).z;
        },
        map[p.landmark].mean, {1});
    const Eigen::Matrix2d S = Eigen::Vector2d(0.01, 0.0001).asDiagonal().toDenseMatrix() +
                              Jl * map[p.landmark].cov * Jl.transpose();
    info += J.transpose() * S.inverse() * J;
  }
  EXPECT_LT((ref.cov - info.inverse()).cwiseAbs().maxCoeff(), 1e-7 * info.inverse().norm());
}
