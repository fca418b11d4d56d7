// Waking up over a window (docs/ALGORITHMS.md "Waking up on a saved map", "Over a window"): a
// start that reads one landmark a step is found once the window's landmarks fix the pose, within
// its covariance of the truth; one landmark read from many poses leaves the rotation about it
// free; a symmetric world read one landmark a step, without ids, is not found. The joint fit
// itself against the latest-pose fit and against the truth.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "WakeUpTestUtil.h"
#include "budget_slam/core/RangeBearingModel.h"
#include "budget_slam/wakeup/GlobalLocalizer.h"
#include "budget_slam/wakeup/WindowFit.h"

using namespace budget_slam;
using namespace budget_slam::wakeup;
using namespace budget_slam::wakeup::test;

namespace {

const ReadingNoise kNoise{0.05, 0.5 * M_PI / 180};

SensorSetup sensor(bool with_ids) {
  SensorSetup s;
  s.on_robot = Pose2(0.2, 0.0, 0.0);
  s.max_range = 30;
  s.fov = 2 * M_PI;
  s.std_range = 0.05;
  s.std_bearing = 0.5 * M_PI / 180;
  s.with_ids = with_ids;
  return s;
}

/// Keeps, at each step, only the readings of the landmark `which(k)` names: the robot reads one
/// landmark a step, as on a map the budget has thinned.
std::vector<Step> oneAStep(std::vector<Step> steps, const std::vector<WorldLandmark>& world,
                           const std::vector<std::size_t>& which, const Pose2& on_robot,
                           const std::vector<Pose2>& path) {
  for (std::size_t k = 0; k < steps.size(); ++k) {
    auto& rs = steps[k].scan->readings;
    // The readings are in landmark order over the landmarks in range: find the kept one by its
    // predicted range (ids may be absent).
    const Pose2 sp = compose(path[k], on_robot);
    const double r = (world[which[k]].p - sp.translation()).norm();
    std::vector<RangeBearingReading> kept;
    for (const auto& rd : rs)
      if (std::abs(rd.range - r) < 0.5) kept.push_back(rd);
    rs = kept;
    // The sensor skipped landmarks in its range: its range is no negative evidence.
    steps[k].scan->max_range = 0;
  }
  return steps;
}

/// The truth's squared Mahalanobis distance from a found pose under its covariance.
double mahalanobis2(const WakeUpResult& r, const Pose2& truth) {
  Eigen::Vector3d e(r.pose.mean.x - truth.x, r.pose.mean.y - truth.y,
                    wrapAngle(r.pose.mean.phi - truth.phi));
  return e.dot(r.pose.cov.inverse() * e);
}

/// Three landmarks, read one a step: the first at steps 0-3, the second at 4-6, the third at 7-9.
const std::vector<WorldLandmark>& threeApart() {
  static const std::vector<WorldLandmark> w = {{7, {1.0, 2.5}}, {8, {4.5, -2.0}}, {9, {8.0, 3.0}}};
  return w;
}
const std::vector<std::size_t> kThreeOneAStep = {0, 0, 0, 0, 1, 1, 1, 2, 2, 2};

}  // namespace

TEST(WakeUpWindow, OneLandmarkAStepThreeOverTenStepsIsFoundWithinItsCovariance) {
  const auto path = straightPath(Pose2(0.0, 0.0, 0.2), 10, 0.8);
  std::size_t found = 0;
  double worst = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    const SensorSetup s = sensor(true);
    const auto steps = oneAStep(stepsAlong(path, threeApart(), s, rng, 0.01), threeApart(),
                                kThreeOneAStep, s.on_robot, path);
    GlobalLocalizer g(mapOf(threeApart(), 0.02), WakeUpOptions{}, kNoise);
    // Steps 0-3 read one landmark: no pose, whatever the odometry.
    for (std::size_t k = 0; k < 4; ++k) {
      ASSERT_EQ(steps[k].scan->readings.size(), 1u);
      EXPECT_EQ(g.add(steps[k]).status, WakeUpStatus::NotFound);
      EXPECT_EQ(g.result().reason, WakeUpReason::TooFewLandmarks);
    }
    for (std::size_t k = 4; k < steps.size() && !g.finished(); ++k) g.add(steps[k]);
    const auto& r = g.result();
    ASSERT_EQ(r.status, WakeUpStatus::Found) << seed << " " << reasonName(r.reason);
    ++found;
    EXPECT_GE(r.steps_used, 5u);  // the second landmark is read at step 4
    EXPECT_GE(r.landmarks, 2u);
    // Within its covariance of the truth: chi-square, 3 degrees of freedom, 99.9%.
    const double m2 = mahalanobis2(r, path[r.steps_used - 1]);
    worst = std::max(worst, m2);
    EXPECT_LT(m2, 16.27) << seed;
  }
  EXPECT_EQ(found, 20u) << "worst " << worst;
}

TEST(WakeUpWindow, OneLandmarkReadFromManyPosesLeavesTheRotationFree) {
  // The joint fit over ten poses that read one landmark: the rotation about it is unobserved
  // (its marginal information is singular), the robot is not found.
  const std::vector<WorldLandmark> world = {{7, {3.0, 2.0}}};
  const auto path = straightPath(Pose2(0.0, 0.0, 0.3), 10, 0.5);
  std::mt19937 rng(4);
  SensorSetup s = sensor(true);
  s.std_range = s.std_bearing = 0;
  const auto steps = stepsAlong(path, world, s, rng, 0.0);
  ReadingWindow w(kNoise, WakeUpOptions{});
  for (const auto& st : steps) w.add(st);
  const auto readings = w.readings();
  ASSERT_EQ(readings.size(), 10u);
  std::vector<Pairing> pairs;
  for (std::size_t i = 0; i < readings.size(); ++i) pairs.push_back({i, 0});
  const auto ref = fitWindow(path.back(), w.gathered(), readings, mapOf(world), pairs, kNoise,
                             WindowLandmarks::Priors);
  const Eigen::Vector3d d = ref.information.diagonal();
  const Eigen::Vector3d sc = d.cwiseSqrt().cwiseInverse();
  const Eigen::Matrix3d C = sc.asDiagonal() * ref.information * sc.asDiagonal();
  EXPECT_LT(std::abs(C.determinant()), 1e-6);
  const auto r = wakeUp(mapOf(world), steps, WakeUpOptions{}, kNoise);
  EXPECT_EQ(r.status, WakeUpStatus::NotFound);
  EXPECT_EQ(r.steps_used, 10u);
}

TEST(WakeUpWindow, JointFitRecoversTheTruthAndItsCovarianceIsTheJointMarginal) {
  // Noise-free readings and odometry: the joint fit lands on the truth from a start 0.5 m and 8
  // degrees off, and its covariance is the latest pose's block of the inverse of the whole
  // window's information, built here from numerical Jacobians of the whitened factors.
  const auto path = straightPath(Pose2(0.0, 0.0, 0.2), 10, 0.8);
  SensorSetup exact = sensor(true);
  exact.std_range = exact.std_bearing = 0;
  std::mt19937 rng(9);
  const auto steps = oneAStep(stepsAlong(path, threeApart(), exact, rng, 0.0), threeApart(),
                              kThreeOneAStep, exact.on_robot, path);
  ReadingWindow w(kNoise, WakeUpOptions{});
  for (const auto& st : steps) w.add(st);
  const auto readings = w.readings();
  const auto gathered = w.gathered();
  const auto map = mapOf(threeApart(), 0.1);
  std::vector<Pairing> pairs;
  for (std::size_t i = 0; i < readings.size(); ++i)
    pairs.push_back({i, static_cast<std::size_t>(readings[i].id - 7)});
  const Pose2 start(path.back().vector() + Eigen::Vector3d(0.4, -0.3, 0.14));
  const auto joint =
      fitWindow(start, gathered, readings, map, pairs, kNoise, WindowLandmarks::Priors);
  ASSERT_TRUE(joint.converged);
  EXPECT_LT((joint.pose.vector() - path.back().vector()).norm(), 1e-7);
  for (const double c : joint.chi2) EXPECT_LT(c, 1e-10);

  // The reference: variables X_0 .. X_9, then l_0 .. l_2; every factor whitened by the Cholesky
  // factor of its covariance.
  const std::size_t n = path.size(), L = map.size(), D = 3 * n + 2 * L;
  const auto whiten = [](const Eigen::MatrixXd& cov, const Eigen::VectorXd& e) -> Eigen::VectorXd {
    const Eigen::MatrixXd c =
        cov + kCovarianceFloor * Eigen::MatrixXd::Identity(cov.rows(), cov.cols());
    return c.llt().matrixL().solve(e);
  };
  const Eigen::Matrix2d Rn =
      Eigen::Vector2d(kNoise.std_range * kNoise.std_range, kNoise.std_bearing * kNoise.std_bearing)
          .asDiagonal();
  const auto residuals = [&](const Eigen::VectorXd& t) {
    std::vector<double> out;
    const auto X = [&](std::size_t j) { return Pose2(t.segment<3>(3 * j)); };
    const auto push = [&](const Eigen::VectorXd& v) {
      for (long i = 0; i < v.size(); ++i) out.push_back(v(i));
    };
    for (std::size_t j = 1; j < n; ++j) {
      Eigen::Vector3d e = gathered[j].odometry.vector() - between(X(j - 1), X(j)).vector();
      e.z() = wrapAngle(e.z());
      push(whiten(gathered[j].odometry_cov, e));
    }
    for (const auto& p : pairs) {
      const std::size_t j = readings[p.reading].step;
      const Eigen::Vector2d l = t.segment<2>(3 * n + 2 * p.landmark);
      Eigen::Vector2d nu = readings[p.reading].z - predictRangeBearing(X(j), exact.on_robot, l).z;
      nu.y() = wrapAngle(nu.y());
      push(whiten(Rn, nu));
    }
    for (std::size_t q = 0; q < L; ++q)
      push(whiten(map[q].cov, map[q].mean - t.segment<2>(3 * n + 2 * q)));
    return Eigen::Map<Eigen::VectorXd>(out.data(), static_cast<long>(out.size())).eval();
  };
  Eigen::VectorXd truth(D);
  for (std::size_t j = 0; j < n; ++j) truth.segment<3>(3 * j) = path[j].vector();
  for (std::size_t q = 0; q < L; ++q) truth.segment<2>(3 * n + 2 * q) = map[q].mean;
  const Eigen::VectorXd r0 = residuals(truth);
  Eigen::MatrixXd J(r0.size(), D);
  const double h = 1e-7;
  for (std::size_t i = 0; i < D; ++i) {
    Eigen::VectorXd a = truth, b = truth;
    a(i) += h;
    b(i) -= h;
    J.col(i) = (residuals(a) - residuals(b)) / (2 * h);
  }
  const Eigen::MatrixXd cov = (J.transpose() * J).inverse();
  const Eigen::Matrix3d expected = cov.block<3, 3>(3 * (n - 1), 3 * (n - 1));
  EXPECT_LT((joint.cov - expected).cwiseAbs().maxCoeff(), 1e-4 * expected.cwiseAbs().maxCoeff())
      << joint.cov << "\n"
      << expected;
  // Landmarks fixed at their means: the poses' block of the same information (the priors' rows
  // touch no pose), inverted without the landmarks.
  const auto fixed =
      fitWindow(start, gathered, readings, map, pairs, kNoise, WindowLandmarks::Fixed);
  ASSERT_TRUE(fixed.converged);
  EXPECT_LT((fixed.pose.vector() - path.back().vector()).norm(), 1e-7);
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::Matrix3d expected_fixed =
      H.topLeftCorner(3 * n, 3 * n).inverse().block<3, 3>(3 * (n - 1), 3 * (n - 1));
  EXPECT_LT((fixed.cov - expected_fixed).cwiseAbs().maxCoeff(),
            1e-4 * expected_fixed.cwiseAbs().maxCoeff());
  // The map's marginals make the pose in the map's frame less certain than the pose relative
  // to the map as drawn.
  EXPECT_GT(joint.cov.trace(), fixed.cov.trace());
}

TEST(WakeUpWindow, ASymmetricWorldReadOneLandmarkAStepWithoutIdsIsNotFound) {
  // Landmarks symmetric under a half-turn about the origin; the robot drives through the centre
  // reading one landmark a step. Without ids the pose and its half-turn explain every reading:
  // never found, at any step.
  std::vector<WorldLandmark> world;
  LandmarkId id = 1;
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(-6, 2), Eigen::Vector2d(-3, -3), Eigen::Vector2d(0, 4),
        Eigen::Vector2d(3, 1.5), Eigen::Vector2d(6, -2.5)}) {
    world.push_back({id++, p});
    world.push_back({id++, -p});
  }
  const auto path = straightPath(Pose2(-5.0, 0.3, 0.05), 20, 0.5);
  // Each step reads the landmark nearest the robot.
  std::vector<std::size_t> which;
  for (const auto& p : path) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < world.size(); ++i)
      if ((world[i].p - p.translation()).norm() < (world[best].p - p.translation()).norm())
        best = i;
    which.push_back(best);
  }
  for (const auto mode : {Correspondence::Search, Correspondence::Auto}) {
    WakeUpOptions o;
    o.max_steps = 20;
    o.correspondence = mode;
    std::mt19937 rng(6);
    const SensorSetup s = sensor(false);
    const auto steps =
        oneAStep(stepsAlong(path, world, s, rng, 0.01), world, which, s.on_robot, path);
    GlobalLocalizer g(mapOf(world), o, kNoise);
    for (const auto& st : steps) {
      g.add(st);
      EXPECT_NE(g.result().status, WakeUpStatus::Found) << st.index;
    }
    EXPECT_EQ(g.result().status, WakeUpStatus::Ambiguous);
    EXPECT_EQ(g.result().steps_used, 20u);
  }
}

TEST(WakeUpWindow, OneLandmarkAStepWithoutIdsIsFoundBySearchOnceFourAreRead) {
  // The same drive through a world without symmetry, no ids: the search pairs the local landmarks
  // merged over the window with the map's; found once search_min_landmarks (4) are read, at the
  // right pose, within its covariance.
  const std::vector<WorldLandmark> world = {
      {1, {-4.5, 2.0}}, {2, {-2.5, -2.5}}, {3, {-0.5, 3.5}}, {4, {1.5, -1.0}}, {5, {3.5, 2.5}},
      {6, {5.5, -3.0}}, {7, {7.5, 1.2}},   {8, {9.5, -1.8}}, {9, {11.5, 4.0}}, {10, {13.5, -2.2}}};
  const auto path = straightPath(Pose2(-5.0, 0.3, 0.05), 20, 1.0);
  std::vector<std::size_t> which;
  for (const auto& p : path) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < world.size(); ++i)
      if ((world[i].p - p.translation()).norm() < (world[best].p - p.translation()).norm())
        best = i;
    which.push_back(best);
  }
  WakeUpOptions o;
  o.max_steps = 20;
  std::mt19937 rng(8);
  const SensorSetup s = sensor(false);
  const auto steps =
      oneAStep(stepsAlong(path, world, s, rng, 0.01), world, which, s.on_robot, path);
  GlobalLocalizer g(mapOf(world), o, kNoise);
  for (const auto& st : steps) {
    if (g.finished()) break;
    g.add(st);
  }
  const auto& r = g.result();
  ASSERT_EQ(r.status, WakeUpStatus::Found) << statusName(r.status) << " " << reasonName(r.reason);
  EXPECT_FALSE(r.by_ids);
  EXPECT_GE(r.landmarks, 4u);
  EXPECT_LT(mahalanobis2(r, path[r.steps_used - 1]), 16.27);
}
