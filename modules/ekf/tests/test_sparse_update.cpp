// The sparse EKF update ([EkfSLAM] update = sparse, the default) against the dense update it
// replaces: the linear algebra against the textbook formula, and whole runs against MRPT's own
// iteration ([EkfSLAM] update = mrpt) at every step, to 1e-9 (docs/PERFORMANCE.md "EKF update").
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "StepsWithoutIds.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/ekf/SparseKalmanUpdate.h"

using namespace budget_slam;
using budget_slam::testing::withoutIds;
using ekf::EkfSlamOptions;

namespace {
const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;

std::string slurpFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The ini file at `path` with [EkfSLAM] update and, when given, the Kalman method set.
std::unique_ptr<mrpt::config::CConfigFileMemory> iniWith(const std::string& path,
                                                         const std::string& update,
                                                         const std::string& method = "") {
  auto ini = std::make_unique<mrpt::config::CConfigFileMemory>(slurpFile(path));
  ini->write("EkfSLAM", "update", update);
  if (!method.empty()) ini->write("RangeBearingKFSLAM_KalmanFilter", "method", method);
  return ini;
}

struct Gap {
  double mean = 0;        ///< largest |x_sparse - x_mrpt| over every step
  double covariance = 0;  ///< largest |P_sparse - P_mrpt| over every step
  std::size_t steps = 0;
  std::size_t landmarks_final = 0;
  std::size_t removals = 0;
};

/// Both updates over the same steps, compared after every step. With `keep` > 0 both drop their
/// oldest landmark until they hold at most `keep` (the budget's removals between updates).
Gap sideBySide(const std::string& ini_path, const std::string& rawlog,
               const std::string& method = "", std::size_t keep = 0,
               const std::function<Step(const Step&)>& transform = nullptr) {
  const auto sparse_ini = iniWith(ini_path, "sparse", method);
  const auto mrpt_ini = iniWith(ini_path, "mrpt", method);
  ekf::EkfBackend sparse(*sparse_ini), mrpt(*mrpt_ini);
  EXPECT_TRUE(sparse.filter().usesSparseUpdate());
  EXPECT_FALSE(mrpt.filter().usesSparseUpdate());
  Gap gap;
  dataset::RawlogReader reader(rawlog);
  while (auto s = reader.next()) {
    const Step step = transform ? transform(*s) : *s;
    sparse.process(step);
    mrpt.process(step);
    ++gap.steps;
    const auto& x1 = sparse.filter().mean().asEigen();
    const auto& x2 = mrpt.filter().mean().asEigen();
    if (x1.size() != x2.size()) {
      ADD_FAILURE() << "state sizes differ at step " << step.index;
      return gap;
    }
    EXPECT_EQ(sparse.lastAssociation(), mrpt.lastAssociation()) << "step " << step.index;
    gap.mean = std::max(gap.mean, (x1 - x2).cwiseAbs().maxCoeff());
    gap.covariance = std::max(gap.covariance, (sparse.filter().covariance().asEigen() -
                                               mrpt.filter().covariance().asEigen())
                                                  .cwiseAbs()
                                                  .maxCoeff());
    const auto& P = sparse.filter().covariance().asEigen();
    EXPECT_TRUE(P.isApprox(P.transpose(), 0.0)) << "not exactly symmetric at step " << step.index;
    while (keep > 0 && sparse.landmarkCount() > keep) {
      const LandmarkId oldest = sparse.idsInStateOrder().front();
      sparse.removeLandmark(oldest);
      mrpt.removeLandmark(oldest);
      ++gap.removals;
    }
  }
  gap.landmarks_final = sparse.landmarkCount();
  return gap;
}

constexpr double kTolerance = 1e-9;

}  // namespace

// The update of a joint reading of several landmarks against the dense textbook form
// K = P Hᵀ S⁻¹, x + K ν, (I - K H) P, on a random state; and the iterated mean of kfIKFFull.
TEST(SparseKalmanUpdate, EqualsTheDenseUpdate) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  const Eigen::Index landmarks = 90, n = 3 + 2 * landmarks;  // several 64 x 64 blocks
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) A(i, j) = normal(rng);
  const Eigen::MatrixXd P0 = A * A.transpose() / double(n) + Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd x0(n);
  for (Eigen::Index i = 0; i < n; ++i) x0[i] = normal(rng);

  std::vector<ekf::ReadingJacobian> H;
  for (const Eigen::Index lm : {4, 77, 2, 89}) {
    ekf::ReadingJacobian h;
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 3; ++c) h.robot(r, c) = normal(rng);
      for (int c = 0; c < 2; ++c) h.landmark(r, c) = normal(rng);
    }
    h.landmark_row = 3 + 2 * lm;
    H.push_back(h);
  }
  const Eigen::Index m2 = 2 * static_cast<Eigen::Index>(H.size());
  Eigen::MatrixXd Hd = Eigen::MatrixXd::Zero(m2, n);
  for (std::size_t k = 0; k < H.size(); ++k) {
    Hd.block<2, 3>(2 * Eigen::Index(k), 0) = H[k].robot;
    Hd.block<2, 2>(2 * Eigen::Index(k), H[k].landmark_row) = H[k].landmark;
  }
  const Eigen::MatrixXd S = Hd * P0 * Hd.transpose() + 0.01 * Eigen::MatrixXd::Identity(m2, m2);
  const Eigen::MatrixXd S_inv = S.inverse();
  Eigen::VectorXd nu(m2);
  for (Eigen::Index i = 0; i < m2; ++i) nu[i] = normal(rng);
  const Eigen::MatrixXd K = P0 * Hd.transpose() * S_inv;
  const Eigen::MatrixXd P_dense = (Eigen::MatrixXd::Identity(n, n) - K * Hd) * P0;

  for (const int iterations : {1, 3}) {
    ekf::RowMajorMatrix P = P0;
    Eigen::VectorXd x = x0;
    ekf::sparseKalmanUpdate(P, x, H, S_inv, nu, iterations);
    Eigen::VectorXd x_dense = x0;
    for (int it = 0; it < iterations; ++it) x_dense = x0 + K * (nu - Hd * (x_dense - x0));
    EXPECT_LT((x - x_dense).cwiseAbs().maxCoeff(), 1e-12) << iterations;
    EXPECT_LT((P - P_dense).cwiseAbs().maxCoeff(), 1e-12) << iterations;
    EXPECT_TRUE(P.isApprox(P.transpose(), 0.0));  // exactly symmetric
  }
  ekf::RowMajorMatrix P = P0;
  Eigen::VectorXd x = x0;
  H[1].landmark_row = n - 1;  // a landmark past the state's end
  EXPECT_THROW(ekf::sparseKalmanUpdate(P, x, H, S_inv, nu), std::invalid_argument);
}

// Issue 38: the sparse update against MRPT's own at every step, on three rawlogs: MRPT's
// kf-slam demo (simulated, 70 landmarks), rooms (simulated, 154 landmarks) and UTIAS MRCLAM 7
// robot 1 (real data, 15 landmarks, 1,663 steps).
TEST(EkfSparseUpdate, EqualsMrptsUpdateOnThreeRawlogs) {
  struct Case {
    std::string ini, rawlog;
    std::size_t steps, landmarks;
  };
  for (const Case& c :
       {Case{"/tests/data/EKF-SLAM_test_2d.ini", "/rawlogs/kf-slam_demo.rawlog", 249, 70},
        Case{"/rawlogs/rooms.ini", "/rawlogs/rooms.rawlog", 424, 154},
        Case{"/rawlogs/mrclam7_robot1.ini", "/rawlogs/mrclam7_robot1.rawlog", 1663, 15}}) {
    const Gap gap = sideBySide(kRoot + c.ini, kRoot + c.rawlog);
    EXPECT_EQ(gap.steps, c.steps) << c.rawlog;
    EXPECT_EQ(gap.landmarks_final, c.landmarks) << c.rawlog;
    EXPECT_LT(gap.mean, kTolerance) << c.rawlog;
    EXPECT_LT(gap.covariance, kTolerance) << c.rawlog;
  }
}

// MRPT's data association (readings without IDs, on the innovation covariance of the predicted
// landmarks), the iterated kfIKFFull, and removals between the updates.
TEST(EkfSparseUpdate, EqualsMrptsUpdateWithDataAssociationIteratedAndRemovals) {
  const std::string ini = kRoot + "/tests/data/EKF-SLAM_test_2d.ini";
  const std::string demo = kRoot + "/rawlogs/kf-slam_demo.rawlog";
  const Gap no_ids = sideBySide(ini, demo, "", 0, withoutIds);
  EXPECT_GT(no_ids.landmarks_final, 50u);
  EXPECT_LT(no_ids.mean, kTolerance);
  EXPECT_LT(no_ids.covariance, kTolerance);

  const Gap iterated = sideBySide(ini, demo, "kfIKFFull");
  EXPECT_EQ(iterated.landmarks_final, 70u);
  EXPECT_LT(iterated.mean, kTolerance);
  EXPECT_LT(iterated.covariance, kTolerance);

  const Gap removals = sideBySide(ini, demo, "", 25);
  EXPECT_GT(removals.removals, 40u);
  EXPECT_LT(removals.mean, kTolerance);
  EXPECT_LT(removals.covariance, kTolerance);
}

// Settings the sparse iteration does not cover run MRPT's own (scalar updates, numeric or
// checked Jacobians), and the key's values are its table's.
TEST(EkfSparseUpdate, OtherMrptSettingsRunMrptsOwnIteration) {
  const std::string ini = kRoot + "/tests/data/EKF-SLAM_test_2d.ini";
  EXPECT_FALSE(
      ekf::EkfBackend(*iniWith(ini, "sparse", "kfEKFAlaDavison")).filter().usesSparseUpdate());
  auto numeric = iniWith(ini, "sparse");
  numeric->write("RangeBearingKFSLAM_KalmanFilter", "use_analytic_observation_jacobian", "false");
  EXPECT_FALSE(ekf::EkfBackend(*numeric).filter().usesSparseUpdate());
  EXPECT_TRUE(ekf::EkfBackend(*iniWith(ini, "sparse", "kfIKFFull")).filter().usesSparseUpdate());

  mrpt::config::CConfigFileMemory bad;
  bad.write("EkfSLAM", "update", "dense");
  try {
    ekf::EkfBackend b(bad);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "[EkfSLAM] update = 'dense': must be one of sparse, mrpt");
  }
}
