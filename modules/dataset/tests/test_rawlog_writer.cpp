#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include "TestUtil.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/dataset/RawlogWriter.h"
#include "budget_slam/dataset/StepToMrpt.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;

namespace {

std::vector<Step> sampleSteps() {
  std::vector<Step> steps;
  for (int k = 0; k < 5; ++k) {
    OdometryIncrement odo;
    odo.mean = {0.1 * k + 0.3, -0.01 * k, 0.05 * (k - 2)};
    odo.cov << 1e-4, 2e-6, 0, 2e-6, 4e-6, 1e-7, 0, 1e-7, 4e-6;
    RangeBearingScan scan;
    scan.sensor_pose_on_robot = {0.1, 0.0, 0.2, 0.05, 0, 0};
    scan.min_range = 0.5;
    scan.max_range = 20.3;
    scan.fov_yaw = M_PI;
    scan.std_range = 0.1;
    scan.std_yaw = 0.01;
    for (int i = 0; i < k; ++i)
      scan.readings.push_back({i == 2 ? kNoLandmarkId : 10 + i, 1.0 / 3 + i, -0.7 + 0.3 * i, 0});
    steps.push_back(makeStep(k, 1.5 + k, odo, scan));
  }
  return steps;
}

void expectSameStep(const Step& a, const Step& b) {
  ASSERT_EQ(a.odometry.has_value(), b.odometry.has_value());
  if (a.odometry) {
    EXPECT_NEAR(a.odometry->mean.x, b.odometry->mean.x, 1e-12);
    EXPECT_NEAR(a.odometry->mean.y, b.odometry->mean.y, 1e-12);
    EXPECT_NEAR(a.odometry->mean.phi, b.odometry->mean.phi, 1e-12);
    EXPECT_LT((a.odometry->cov - b.odometry->cov).cwiseAbs().maxCoeff(), 1e-12);
  }
  EXPECT_NEAR(a.t, b.t, 1e-6);  // MRPT keeps 100 ns ticks
  ASSERT_EQ(a.scan.has_value(), b.scan.has_value());
  if (!a.scan) return;
  const auto &s = *a.scan, &r = *b.scan;
  EXPECT_NEAR(s.min_range, r.min_range, 1e-12);
  EXPECT_NEAR(s.max_range, r.max_range, 1e-12);
  EXPECT_NEAR(s.fov_yaw, r.fov_yaw, 1e-12);
  EXPECT_NEAR(s.std_range, r.std_range, 1e-12);
  EXPECT_NEAR(s.std_yaw, r.std_yaw, 1e-12);
  EXPECT_NEAR(s.sensor_pose_on_robot.x, r.sensor_pose_on_robot.x, 1e-12);
  EXPECT_NEAR(s.sensor_pose_on_robot.z, r.sensor_pose_on_robot.z, 1e-12);
  EXPECT_NEAR(s.sensor_pose_on_robot.yaw, r.sensor_pose_on_robot.yaw, 1e-12);
  ASSERT_EQ(s.readings.size(), r.readings.size());
  for (std::size_t i = 0; i < s.readings.size(); ++i) {
    EXPECT_EQ(s.readings[i].id, r.readings[i].id);
    EXPECT_NEAR(s.readings[i].range, r.readings[i].range, 1e-12);
    EXPECT_NEAR(s.readings[i].yaw, r.readings[i].yaw, 1e-12);
  }
}

}  // namespace

TEST(StepToMrpt, ActionIsTheGaussianKfSlamReads) {
  OdometryIncrement odo;
  odo.mean = {1.0, 0.5, 4.0};  // yaw outside (-pi, pi]: MRPT wraps it
  odo.cov = Eigen::Vector3d(0.01, 0.02, 0.03).asDiagonal();
  const auto action = makeAction(odo, 10.0);
  const auto best = action->getBestMovementEstimation();
  ASSERT_TRUE(best);
  mrpt::poses::CPose2D mean;
  mrpt::math::CMatrixDouble33 cov;
  best->poseChange->getCovarianceAndMean(cov, mean);
  EXPECT_DOUBLE_EQ(mean.x(), 1.0);
  EXPECT_NEAR(mean.phi(), 4.0 - 2 * M_PI, 1e-15);
  EXPECT_DOUBLE_EQ(cov(2, 2), 0.03);
  EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(best->timestamp), 10.0);
  const auto step = makeStep(0, 10.0, odo, std::nullopt);
  EXPECT_NEAR(step.odometry->mean.phi, 4.0 - 2 * M_PI, 1e-15);
  EXPECT_FALSE(step.scan);
  EXPECT_EQ(step.frame->size(), 0u);
}

TEST(StepToMrpt, FrameHoldsOneBearingRangeObservation) {
  const auto steps = sampleSteps();
  const auto obs = steps[4].frame->getObservationByClass<mrpt::obs::CObservationBearingRange>();
  ASSERT_TRUE(obs);
  EXPECT_EQ(steps[4].frame->size(), 1u);
  ASSERT_EQ(obs->sensedData.size(), 4u);
  EXPECT_EQ(obs->sensedData[0].landmarkID, 10);
  EXPECT_EQ(obs->sensedData[2].landmarkID, mrpt::obs::INVALID_LANDMARK_ID);
  EXPECT_FLOAT_EQ(obs->maxSensorDistance, 20.3f);
  EXPECT_FLOAT_EQ(obs->sensor_std_yaw, 0.01f);
  EXPECT_DOUBLE_EQ(obs->sensorLocationOnRobot.z(), 0.2);
  // The parsed fields hold the float values MRPT stores.
  EXPECT_EQ(steps[4].scan->readings[1].range, static_cast<double>(obs->sensedData[1].range));
}

TEST(StepToMrpt, RejectsIdsMrptCannotStore) {
  RangeBearingScan scan;
  scan.readings = {{5, 1, 0, 0}, {5, 2, 0, 0}};
  EXPECT_EQ(inputErrorOf([&] { makeFrame(scan, 1); }),
            "landmark id 5 appears twice in one observation");
  scan.readings = {{1LL << 40, 1, 0, 0}};
  EXPECT_EQ(inputErrorOf([&] { makeFrame(scan, 1); }),
            "landmark id 1099511627776 does not fit MRPT's int32");
  EXPECT_EQ(inputErrorOf([&] { makeStep(0, 0.0, std::nullopt, std::nullopt); }),
            "timestamp 0.000000 s is not a positive finite time");
}

TEST(RawlogWriter, MrptReadsBackTheSamePairs) {
  TempDir tmp;
  const auto steps = sampleSteps();
  writeRawlog(tmp.file("a.rawlog"), steps);
  mrpt::io::CFileGZInputStream in(tmp.file("a.rawlog"));
  auto arch = mrpt::serialization::archiveFrom(in);
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr frame;
  std::size_t entry = 0, k = 0;
  while (mrpt::obs::CRawlog::readActionObservationPair(arch, action, frame, entry)) {
    ASSERT_LT(k, steps.size());
    expectSameStep(steps[k], parseStep(action, frame, k, 0));
    ++k;
  }
  EXPECT_EQ(k, steps.size());
}

TEST(RawlogWriter, RawlogReaderReadsBackTheSameSteps) {
  TempDir tmp;
  const auto steps = sampleSteps();
  writeRawlog(tmp.file("a.rawlog"), steps);
  const auto back = readAllSteps(tmp.file("a.rawlog"));
  ASSERT_EQ(back.size(), steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) expectSameStep(steps[k], back[k]);
}

TEST(RawlogWriter, SameStepsSameBytes) {
  TempDir tmp;
  writeRawlog(tmp.file("a.rawlog"), sampleSteps());
  writeRawlog(tmp.file("b.rawlog"), sampleSteps());
  const auto a = readFile(tmp.file("a.rawlog"));
  EXPECT_GT(a.size(), 100u);
  EXPECT_EQ(a, readFile(tmp.file("b.rawlog")));
}

TEST(RawlogWriter, RawlogEditInfoReadsIt) {
  TempDir tmp;
  writeRawlog(tmp.file("a.rawlog"), sampleSteps());
  const std::string out = tmp.file("info.txt");
  ASSERT_EQ(run("rawlog-edit --info -i '" + tmp.file("a.rawlog") + "' > '" + out + "' 2>&1"), 0);
  const auto info = readFile(out);
  // 5 steps = 5 actions + 5 frames, in the actions-observations form.
  EXPECT_NE(info.find("Overall number of objects         : 10"), std::string::npos) << info;
  EXPECT_NE(info.find("Actions/SensoryFrame format       : Yes"), std::string::npos) << info;
  EXPECT_NE(info.find("BEARING_RANGE /      5"), std::string::npos) << info;
}

TEST(RawlogWriter, UnwritablePathIsAnErrorNamingTheFile) {
  std::string what;
  try {
    RawlogWriter w("/nonexistent-dir/x.rawlog");
  } catch (const Error& e) {
    what = e.what();
  }
  EXPECT_EQ(what, "cannot write '/nonexistent-dir/x.rawlog' (No such file or directory)");
}

// Written under a temporary name: a writer that does not finish leaves no rawlog at all.
TEST(RawlogWriter, AnUnfinishedRawlogLeavesNoFile) {
  TempDir tmp;
  {
    RawlogWriter w(tmp.file("a.rawlog"));
    for (const auto& s : sampleSteps()) w.write(s);
  }
  EXPECT_FALSE(fileExists(tmp.file("a.rawlog")));
  EXPECT_FALSE(fileExists(tmp.file("a.rawlog.tmp")));
}
