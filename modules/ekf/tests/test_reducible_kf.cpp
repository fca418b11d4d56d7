#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <map>
#include <set>

#include "StepsWithoutIds.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"

using namespace budget_slam;
using budget_slam::testing::withoutIds;

namespace {
const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
const std::string kDemo = kRoot + "/rawlogs/kf-slam_demo.rawlog";
const std::string kIni = kRoot + "/tests/data/EKF-SLAM_test_2d.ini";

}  // namespace

// docs/ARCHITECTURE.md "EKF backend": with no reducer, a run gives the same final state as MRPT's
// own filter.
TEST(EkfBackend, WithoutRemovalsEqualsMrptsOwnFilter) {
  mrpt::config::CConfigFile ini(kIni);

  mrpt::slam::CRangeBearingKFSLAM2D reference;
  reference.loadOptions(ini);
  {
    mrpt::io::CFileGZInputStream f(kDemo);
    auto arch = mrpt::serialization::archiveFrom(f);
    mrpt::obs::CActionCollection::Ptr action;
    mrpt::obs::CSensoryFrame::Ptr frame;
    size_t entry = 0;
    while (mrpt::obs::CRawlog::readActionObservationPair(arch, action, frame, entry))
      reference.processActionObservation(action, frame);
  }

  ekf::EkfBackend backend(ini);
  dataset::RawlogReader reader(kDemo);
  std::size_t steps = 0;
  while (auto s = reader.next()) backend.process(*s), ++steps;
  EXPECT_EQ(steps, 249u);

  mrpt::poses::CPosePDFGaussian pose;
  std::vector<mrpt::math::TPoint2D> lms;
  std::map<unsigned int, mrpt::maps::CLandmark::TLandmarkID> ids;
  mrpt::math::CVectorDouble x;
  mrpt::math::CMatrixDouble P;
  reference.getCurrentState(pose, lms, ids, x, P);

  const auto& x2 = backend.filter().mean();
  const auto& P2 = backend.filter().covariance();
  ASSERT_EQ(x.size(), x2.size());
  ASSERT_EQ(lms.size(), 70u);
  for (int i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], x2[i], 1e-9) << i;
  EXPECT_LT((P.asEigen() - P2.asEigen()).cwiseAbs().maxCoeff(), 1e-9);
  const auto views = backend.landmarks();
  for (std::size_t i = 0; i < views.size(); ++i) {
    EXPECT_EQ(views[i].id, ids.at(static_cast<unsigned>(i)));
    EXPECT_NEAR(views[i].mean.x(), lms[i].x, 1e-9);
    EXPECT_NEAR(views[i].mean.y(), lms[i].y, 1e-9);
  }
  EXPECT_NEAR(backend.robotPose().mean.x, pose.mean.x(), 1e-9);
  EXPECT_NEAR(backend.robotPose().mean.phi, pose.mean.phi(), 1e-9);
}

TEST(EkfBackend, RemovalDeletesRowsAndColumnsAndKeepsIdsConsistent) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  auto steps = dataset::readAllSteps(kDemo);
  for (std::size_t k = 0; k < 120; ++k) backend.process(steps[k]);

  const auto before = backend.landmarks();
  ASSERT_GT(before.size(), 10u);
  const Eigen::MatrixXd P = backend.filter().covariance().asEigen();
  const Eigen::VectorXd x = backend.filter().mean().asEigen();
  const std::size_t victim_index = 4;
  const LandmarkId victim = before[victim_index].id;

  backend.removeLandmark(victim);

  const Eigen::Index r = static_cast<Eigen::Index>(3 + 2 * victim_index), n = P.rows();
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < n; ++i)
    if (i != r && i != r + 1) keep.push_back(i);
  const auto& P2 = backend.filter().covariance().asEigen();
  const auto& x2 = backend.filter().mean();
  ASSERT_EQ(P2.rows(), n - 2);
  for (std::size_t i = 0; i < keep.size(); ++i) {
    EXPECT_EQ(x2[i], x[keep[i]]);
    for (std::size_t j = 0; j < keep.size(); ++j) ASSERT_EQ(P2(i, j), P(keep[i], keep[j]));
  }
  // Every remaining id still names the same landmark.
  const auto after = backend.landmarks();
  ASSERT_EQ(after.size(), before.size() - 1);
  for (const auto& v : after) {
    const auto it =
        std::find_if(before.begin(), before.end(), [&](auto& b) { return b.id == v.id; });
    ASSERT_NE(it, before.end());
    EXPECT_EQ(v.mean, it->mean);
    EXPECT_EQ(v.n_obs, it->n_obs);
  }
  EXPECT_THROW(backend.removeLandmark(victim), std::out_of_range);

  // The filter runs on; a re-sighted sensor ID comes back as a new landmark.
  for (std::size_t k = 120; k < steps.size(); ++k) backend.process(steps[k]);
  const auto final_views = backend.landmarks();
  std::set<LandmarkId> seen;
  for (const auto& v : final_views) EXPECT_TRUE(seen.insert(v.id).second) << "duplicate id";
  EXPECT_EQ(final_views.size(), 70u);
  const auto it =
      std::find_if(final_views.begin(), final_views.end(), [&](auto& v) { return v.id == victim; });
  ASSERT_NE(it, final_views.end());
  EXPECT_GT(it->first_step, 119u);
}

TEST(EkfBackend, IdLessLandmarksNeverReuseAnIdAcrossManyRemovals) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  std::set<LandmarkId> ever;
  std::set<LandmarkId> current;
  std::size_t removals = 0;
  for (const auto& s : dataset::readAllSteps(kDemo)) {
    backend.process(withoutIds(s));
    for (const auto& v : backend.landmarks())
      if (!current.count(v.id)) {
        EXPECT_TRUE(ever.insert(v.id).second) << "id " << v.id << " reused at step " << s.index;
        current.insert(v.id);
      }
    // Keep only 6 landmarks: drop the oldest until under that.
    while (backend.landmarkCount() > 6) {
      const auto views = backend.landmarks();
      backend.removeLandmark(views.front().id);
      current.erase(views.front().id);
      ++removals;
    }
  }
  EXPECT_GT(removals, 50u);
  EXPECT_GT(ever.size(), 56u);
}

TEST(EkfBackend, FrameWithoutBearingRangeIsPredictionOnly) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  auto steps = dataset::readAllSteps(kDemo);
  for (std::size_t k = 0; k < 20; ++k) backend.process(steps[k]);
  const auto lms = backend.landmarks();
  const auto pose = backend.robotPose();

  Step blind = steps[20];
  blind.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
  blind.scan.reset();
  backend.process(blind);

  const auto lms2 = backend.landmarks();
  ASSERT_EQ(lms2.size(), lms.size());
  for (std::size_t i = 0; i < lms.size(); ++i) EXPECT_EQ(lms2[i].mean, lms[i].mean);
  // Odometry composed onto the pose and its uncertainty grew.
  const auto p2 = backend.robotPose();
  const auto& odo = steps[20].odometry->mean;
  const double c = std::cos(pose.mean.phi), s = std::sin(pose.mean.phi);
  EXPECT_NEAR(p2.mean.x, pose.mean.x + c * odo.x - s * odo.y, 1e-12);
  EXPECT_NEAR(p2.mean.y, pose.mean.y + s * odo.x + c * odo.y, 1e-12);
  EXPECT_GT(p2.cov.determinant(), pose.cov.determinant());
}
