// GraphBackend behind the Backend interface: steps in, batch optimum out, landmark views,
// removal, pose marginalization, association without ids.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include "TestGraphs.h"
#include "budget_slam/graph/GraphBackend.h"

#include "budget_slam/graph/InformationGain.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
RangeBearingNoise noiseOf() { return testgraphs::sensorNoise(0.05, 0.01 * 180 / M_PI); }

double maxDiff(const FactorGraph& g, const Eigen::VectorXd& ref) {
  Eigen::VectorXd d = g.values() - ref;
  for (const auto& [s, p] : g.poses()) d[p.col + 2] = wrapAngle(d[p.col + 2]);
  return d.lpNorm<Eigen::Infinity>();
}
}  // namespace

TEST(GraphBackend, FinishGivesTheBatchOptimum) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(120, 20, 3);
  GraphBackend b(GraphSlamOptions{}, noiseOf());
  for (const Step& s : run.steps) b.process(s);
  EXPECT_GT(b.updateCount(), 5u);
  b.finish();
  EXPECT_EQ(b.name(), "graph");
  EXPECT_EQ(b.poseCount(), 120u);
  EXPECT_LT(maxDiff(b.graph(), testgraphs::denseBatchSolve(b.graph())), 1e-9);
  // Close to the truth, the sensor offset included.
  const std::vector<TrajectoryPoint> tr = b.trajectory();
  ASSERT_EQ(tr.size(), 120u);
  for (std::size_t k = 0; k < tr.size(); ++k) {
    EXPECT_EQ(tr[k].step, k);
    EXPECT_DOUBLE_EQ(tr[k].t, 0.1 * k);
    EXPECT_LT(std::hypot(tr[k].pose.x - run.truth[k].x, tr[k].pose.y - run.truth[k].y), 0.3);
  }
  for (const LandmarkView& v : b.landmarks())
    EXPECT_LT((v.mean - run.landmarks[v.id]).norm(), 0.3) << v.id;
}

TEST(GraphBackend, SensorPoseOnRobotIsRespected) {
  // Readings made by a sensor 1.7 m off the robot's origin and turned 0.4 rad: with the mount
  // respected the residuals are white (chi2 / dof near 1); the same steps with the mount erased
  // from the scans do not fit.
  const Pose2 sensor(1.5, -0.8, 0.4);
  testgraphs::SyntheticRun run = testgraphs::syntheticRun(80, 16, 4, true, 8.0, sensor);
  auto chi2PerDof = [](const std::vector<Step>& steps, GraphBackend* b) {
    for (const Step& s : steps) b->process(s);
    const SolveReport r = b->optimize();
    std::size_t readings = 0;
    for (const auto& [id, l] : b->graph().landmarks()) readings += l.obs.size();
    return r.final_chi2 / static_cast<double>(2 * readings - 2 * b->landmarkCount());
  };
  GraphBackend right(GraphSlamOptions{}, noiseOf());
  EXPECT_LT(chi2PerDof(run.steps, &right), 1.3);
  for (const LandmarkView& v : right.landmarks())
    EXPECT_LT((v.mean - run.landmarks[v.id]).norm(), 0.6) << v.id;
  for (Step& s : run.steps) s.scan->sensor_pose_on_robot = mrpt::math::TPose3D(0, 0, 0, 0, 0, 0);
  GraphBackend wrong(GraphSlamOptions{}, noiseOf());
  EXPECT_GT(chi2PerDof(run.steps, &wrong), 10.0);
}

TEST(GraphBackend, LandmarkViewsTrackSightings) {
  // No update before finish(): the estimate at each sighting is dead reckoning, which the test
  // recomputes to check the running mean of the observation positions.
  GraphSlamOptions opt;
  opt.relinearize_every = 0;
  opt.relinearize_chi2 = 0;
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(60, 12, 5);
  GraphBackend b(opt, noiseOf());
  std::map<LandmarkId, std::vector<Eigen::Vector2d>> seen_from;
  std::map<LandmarkId, std::pair<StepIndex, StepIndex>> span;
  Pose2 x(0, 0, 0);
  for (const Step& s : run.steps) {
    x = compose(x, s.odometry->mean);
    for (const RangeBearingReading& z : s.scan->readings) {
      seen_from[z.id].push_back(x.translation());
      if (!span.count(z.id)) span[z.id].first = s.index;
      span[z.id].second = s.index;
    }
    b.process(s);
  }
  const std::vector<LandmarkView> views = b.landmarks();
  ASSERT_EQ(views.size(), seen_from.size());
  for (const LandmarkView& v : views) {
    const auto& from = seen_from.at(v.id);
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : from) mean += p / static_cast<double>(from.size());
    EXPECT_EQ(v.n_obs, from.size());
    EXPECT_LT((v.obs_mean - mean).norm(), 1e-6);
    EXPECT_EQ(v.first_step, span.at(v.id).first);
    EXPECT_EQ(v.last_step, span.at(v.id).second);
    EXPECT_TRUE(v.cov.isApprox(b.landmarkCovariance(v.id), 1e-12));
    EXPECT_GT(v.cov.determinant(), 0);
  }
}

TEST(GraphBackend, CovariancesAgreeAcrossQueries) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(50, 12, 6);
  GraphSlamOptions opt;
  opt.exact_pose_covariance = true;
  GraphBackend b(opt, noiseOf());
  for (const Step& s : run.steps) b.process(s);
  const PoseEstimate p = b.robotPose();
  EXPECT_NEAR(p.mean.x, b.trajectory().back().pose.x, 0);
  const LandmarkId l = b.landmarks().front().id;
  const Eigen::MatrixXd J = b.jointCovariance({VariableKey::landmark(l), VariableKey::pose(49)});
  ASSERT_EQ(J.rows(), 5);
  EXPECT_TRUE((J.topLeftCorner<2, 2>().isApprox(b.landmarkCovariance(l), 1e-10)));
  EXPECT_TRUE((J.bottomRightCorner<3, 3>().isApprox(p.cov, 1e-10)));
  EXPECT_THROW(b.jointCovariance({VariableKey::pose(999)}), std::out_of_range);
  EXPECT_THROW(b.landmarkCovariance(12345), std::out_of_range);
  // The backend's gains are the fast formula at its estimate; they equal the naive reference.
  std::vector<LandmarkId> ids;
  for (const LandmarkView& v : b.landmarks()) ids.push_back(v.id);
  const std::vector<double> ig = b.informationGain(ids);
  for (std::size_t k = 0; k < ids.size(); ++k)
    EXPECT_NEAR(ig[k], naiveInformationGain(b.graph(), ids[k]), 1e-9 * std::max(1.0, ig[k]));
}

TEST(GraphBackend, RemoveLandmarkDeletesItAndItsFactors) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(60, 12, 7);
  GraphBackend b(GraphSlamOptions{}, noiseOf());
  for (int k = 0; k < 30; ++k) b.process(run.steps[k]);
  const LandmarkId victim = b.landmarks().front().id;
  const std::size_t n = b.landmarkCount(), factors = b.graph().factorCount();
  const std::size_t sightings = b.graph().landmark(victim).obs.size();
  b.removeLandmark(victim);
  EXPECT_EQ(b.landmarkCount(), n - 1);
  EXPECT_EQ(b.graph().factorCount(), factors - sightings);
  EXPECT_THROW(b.removeLandmark(victim), std::out_of_range);
  for (const LandmarkView& v : b.landmarks()) EXPECT_NE(v.id, victim);
  // Seen again later: back as a new landmark.
  StepIndex again = 0;
  for (int k = 30; k < 60; ++k) {
    b.process(run.steps[k]);
    for (const auto& z : run.steps[k].scan->readings)
      if (z.id == victim && again == 0) again = k;
  }
  ASSERT_GT(again, 0u);
  for (const LandmarkView& v : b.landmarks()) {
    if (v.id == victim) {
      EXPECT_EQ(v.first_step, again);
    }
  }
  b.finish();
  EXPECT_LT(maxDiff(b.graph(), testgraphs::denseBatchSolve(b.graph())), 1e-9);
}

TEST(GraphBackend, MarginalizesPosesThatSeeNothing) {
  testgraphs::SyntheticRun run = testgraphs::syntheticRun(60, 12, 8);
  for (int k = 10; k < 40; ++k)
    if (k % 3) run.steps[k].scan.reset();  // prediction-only steps
  GraphBackend b(GraphSlamOptions{}, noiseOf());
  for (const Step& s : run.steps) b.process(s);
  b.finish();
  const PoseEstimate before = b.robotPose();
  const std::map<StepIndex, PoseNode> poses = b.graph().poses();
  const std::size_t n = b.marginalizePosesWithoutLandmarks(5);
  EXPECT_EQ(n, 20u);
  EXPECT_EQ(b.poseCount(), 40u);
  for (const auto& [s, p] : b.graph().poses()) EXPECT_TRUE(p.n_obs > 0 || s == 0 || s >= 55);
  // Composition is exact in the linearized problem: at the optimum, the kept poses stay put and
  // the latest pose's marginal barely moves.
  b.finish();
  for (const auto& [s, p] : b.graph().poses())
    EXPECT_LT((p.x - poses.at(s).x).head<2>().norm(), 1e-3) << s;
  const PoseEstimate after = b.robotPose();
  EXPECT_NEAR(after.cov.determinant() / before.cov.determinant(), 1.0, 1e-2);
  EXPECT_EQ(b.marginalizePosesWithoutLandmarks(5), 0u);
}

TEST(GraphBackend, StepWithoutOdometryStaysPut) {
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(10, 8, 9);
  GraphSlamOptions opt;
  opt.relinearize_every = 0;
  opt.relinearize_chi2 = 0;
  GraphBackend b(opt, noiseOf());
  for (int k = 0; k < 5; ++k) b.process(run.steps[k]);
  Step still = run.steps[5];
  still.odometry.reset();
  still.scan.reset();
  const TrajectoryPoint last = b.trajectory().back();
  b.process(still);
  EXPECT_EQ(b.trajectory().back().step, 5u);
  EXPECT_NEAR(b.trajectory().back().pose.x, last.pose.x, 1e-12);
  EXPECT_NEAR(b.trajectory().back().pose.phi, last.pose.phi, 1e-12);
}

TEST(GraphBackend, AssociatesReadingsWithoutIds) {
  // Landmarks about 5 m apart, pose drift of a few cm: a wide gate (chi2 25, 5 sigma) never
  // confuses two landmarks, and a 99 % gate would open a new one for 1 % of the sightings.
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(80, 12, 10, /*with_ids=*/false);
  GraphSlamOptions opt;
  opt.association_gate_chi2 = 25;
  GraphBackend b(opt, noiseOf());
  for (const Step& s : run.steps) b.process(s);
  b.finish();
  EXPECT_EQ(b.landmarkCount(), 12u);
  for (const LandmarkView& v : b.landmarks()) {
    double best = 1e9;
    for (const auto& l : run.landmarks) best = std::min(best, (v.mean - l).norm());
    EXPECT_LT(best, 0.3);
  }
}

TEST(GraphBackend, PoseCovarianceBetweenFactorizationsIsConservative) {
  // Between updates the latest pose's covariance is the last factorized one propagated through
  // odometry: never smaller than the exact marginal; exact again after finish().
  const testgraphs::SyntheticRun run = testgraphs::syntheticRun(47, 12, 11);
  GraphSlamOptions opt;
  opt.relinearize_chi2 = 0;  // updates at steps 9, 19, ..., 39 only
  GraphBackend cheap(opt, noiseOf());
  opt.exact_pose_covariance = true;
  GraphBackend exact(opt, noiseOf());
  for (const Step& s : run.steps) {
    cheap.process(s);
    exact.process(s);
  }
  const Eigen::Matrix3d c = cheap.robotPose().cov, e = exact.robotPose().cov;
  EXPECT_GT((c - e).norm(), 1e-3 * e.norm());  // 7 steps since the last update: they differ
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c - e).eigenvalues().minCoeff(), -1e-12);
  cheap.finish();
  exact.finish();
  EXPECT_TRUE(cheap.robotPose().cov.isApprox(exact.robotPose().cov, 1e-9));
}
