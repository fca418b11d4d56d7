// EkfBackend::clone(): a copy of MRPT's filter that gives the same state and gains as the
// original and evolves on its own (the look-ahead copy of Choudhary et al. Alg. 3).
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFile.h>
#include "BackendExpectations.h"

#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"

using namespace budget_slam;

namespace {
const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
}  // namespace

TEST(EkfClone, GivesTheSameStateAndEvolvesIndependently) {
  mrpt::config::CConfigFile ini(kRoot + "/tests/data/EKF-SLAM_test_2d.ini");
  ekf::EkfBackend b(ini);
  dataset::RawlogReader reader(kRoot + "/rawlogs/kf-slam_demo.rawlog");
  std::vector<Step> steps;
  while (auto s = reader.next()) steps.push_back(std::move(*s));
  for (std::size_t k = 0; k < 120; ++k) b.process(steps[k]);
  const std::size_t n = b.landmarkCount();
  ASSERT_GT(n, 10u);

  std::unique_ptr<Backend> copy = b.clone();
  ASSERT_NE(copy, nullptr);
  budget_slam::testing::expectSameBackend(b, *copy);
  std::unique_ptr<Backend> twin = b.clone();

  // Removals and steps on the copy leave the original alone.
  const auto ids = budget_slam::testing::idsOf(b);
  const auto gains = b.informationGain(ids);
  copy->removeLandmark(ids[0]);
  copy->removeLandmark(ids[3]);
  for (std::size_t k = 120; k < 130; ++k) copy->process(steps[k]);
  EXPECT_EQ(b.landmarkCount(), n);
  EXPECT_EQ(b.trajectory().size(), 120u);
  EXPECT_EQ(b.informationGain(ids), gains);
  EXPECT_NE(copy->robotPose().mean.vector(), b.robotPose().mean.vector());

  // Original and twin fed the same steps stay identical.
  for (std::size_t k = 120; k < steps.size(); ++k) {
    b.process(steps[k]);
    twin->process(steps[k]);
  }
  budget_slam::testing::expectSameBackend(b, *twin);
}
