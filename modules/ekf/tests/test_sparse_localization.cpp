// The relocalization filter's sparse iteration ([EkfSLAM] update = sparse, the default) against
// MRPT's own (update = mrpt) at every step of a relocalization, to 1e-9 on the whole state, with
// the same gate decisions (docs/PERFORMANCE.md "Relocalization's update").
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <fstream>
#include <functional>
#include <sstream>

#include "StepsWithoutIds.h"
#include "budget_slam/core/MrptPose.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/dataset/Simulator.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/ekf/LocalizationKF2D.h"

using namespace budget_slam;
using budget_slam::ekf::EkfSlamOptions;
using budget_slam::ekf::LocalizationKF2D;
using budget_slam::testing::withoutIds;

namespace {
const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
constexpr double kTolerance = 1e-9;
constexpr double kDeg = M_PI / 180;

std::unique_ptr<mrpt::config::CConfigFileMemory> iniAt(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return std::make_unique<mrpt::config::CConfigFileMemory>(s.str());
}

std::vector<Step> stepsOf(const std::string& rawlog) {
  std::vector<Step> steps;
  dataset::RawlogReader reader(rawlog);
  while (auto s = reader.next()) steps.push_back(*s);
  return steps;
}

/// The map a mapping run ends with (the EKF backend over `steps`, no budget): what `localize`
/// reads back from a map folder (means and marginal covariances).
std::vector<LandmarkView> mapOf(const mrpt::config::CConfigFileBase& ini,
                                const std::vector<Step>& steps) {
  ekf::EkfBackend mapping(ini);
  for (const Step& s : steps) mapping.process(s);
  return mapping.landmarks();
}

/// One relocalization per update; the largest differences and the gate's counts.
struct Gap {
  double mean = 0;        ///< largest |x_sparse - x_mrpt| (yaw wrapped) over every step
  double covariance = 0;  ///< largest |P_sparse - P_mrpt| over every step
  std::size_t steps = 0, used = 0, gated = 0, recoveries = 0;
};

/// Both filters (MRPT's sections of `ini`, `gate`, the same start and map) over `steps`, compared
/// after every step: the state and its covariance, and per reading which landmark it updated,
/// how many were gated, consistent with the map, and whether the step recovered.
Gap sideBySide(const mrpt::config::CConfigFileBase& ini, const std::vector<LandmarkView>& map,
               const PoseEstimate& start, const std::vector<Step>& steps,
               const LocalizationKF2D::Gate& gate) {
  LocalizationKF2D sparse, mrpt;
  for (auto* kf : {&sparse, &mrpt}) {
    kf->loadOptions(ini);
    kf->KF_options.verbosity_level = mrpt::system::LVL_ERROR;
    kf->gate = gate;
    kf->initialize(start, map);
  }
  mrpt.setUpdate(EkfSlamOptions::Update::Mrpt);
  EXPECT_TRUE(sparse.usesSparseUpdate());
  EXPECT_FALSE(mrpt.usesSparseUpdate());
  Gap gap;
  for (const Step& step : steps) {
    sparse.processStep(step);
    mrpt.processStep(step);
    ++gap.steps;
    EXPECT_EQ(sparse.lastUsed(), mrpt.lastUsed()) << "step " << step.index;
    EXPECT_EQ(sparse.lastGated(), mrpt.lastGated()) << "step " << step.index;
    EXPECT_EQ(sparse.lastConsistent(), mrpt.lastConsistent()) << "step " << step.index;
    EXPECT_EQ(sparse.lastRecovered(), mrpt.lastRecovered()) << "step " << step.index;
    for (const LandmarkId id : sparse.lastUsed()) gap.used += id != kNoLandmarkId;
    gap.gated += sparse.lastGated();
    gap.recoveries += sparse.lastRecovered();
    Eigen::VectorXd dx = sparse.mean().asEigen() - mrpt.mean().asEigen();
    dx[2] = mrpt::math::wrapToPi(dx[2]);
    gap.mean = std::max(gap.mean, dx.cwiseAbs().maxCoeff());
    gap.covariance = std::max(
        gap.covariance,
        (sparse.covariance().asEigen() - mrpt.covariance().asEigen()).cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(sparse.landmarkCount(), map.size());  // no landmark entered in either
  EXPECT_EQ(mrpt.landmarkCount(), map.size());
  return gap;
}

PoseEstimate startAt(double x, double y, double yaw) {
  PoseEstimate p;
  p.mean = Pose2(x, y, yaw);
  p.cov = Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal();  // 0.1 m, 1.8 deg
  return p;
}

const LocalizationKF2D::Gate kDefaultGate{13.8, 5, 20, 3};  // [Localization]'s defaults

}  // namespace

// Three shipped rawlogs, each relocalized in the map of its own mapping run: from the mapping's
// start (the readings agree with the map), from a start 0.6 m and 12 deg off with the gate (it
// rejects, then recovers), and, on the kf-slam demo, with readings without ids (MRPT's data
// association against the map, on the innovation covariance each iteration builds).
TEST(SparseLocalization, EqualsMrptsIterationWithTheSameGateDecisionsOnThreeRawlogs) {
  struct Case {
    std::string ini, rawlog;
    std::size_t steps;
  };
  std::size_t recoveries = 0;
  for (const Case& c :
       {Case{"/tests/data/EKF-SLAM_test_2d.ini", "/rawlogs/kf-slam_demo.rawlog", 249},
        Case{"/rawlogs/rooms.ini", "/rawlogs/rooms.rawlog", 424},
        Case{"/rawlogs/mrclam7_robot1.ini", "/rawlogs/mrclam7_robot1.rawlog", 1663}}) {
    const auto ini = iniAt(kRoot + c.ini);
    const auto steps = stepsOf(kRoot + c.rawlog);
    const auto map = mapOf(*ini, steps);
    ASSERT_GT(map.size(), 10u) << c.rawlog;

    const Gap on = sideBySide(*ini, map, startAt(0, 0, 0), steps, kDefaultGate);
    EXPECT_EQ(on.steps, c.steps) << c.rawlog;
    EXPECT_GT(on.used, c.steps) << c.rawlog;
    EXPECT_LT(on.mean, kTolerance) << c.rawlog;
    EXPECT_LT(on.covariance, kTolerance) << c.rawlog;

    const Gap off = sideBySide(*ini, map, startAt(0.6, -0.4, 12 * kDeg), steps, kDefaultGate);
    EXPECT_GT(off.gated, 0u) << c.rawlog;
    recoveries += off.recoveries;
    EXPECT_LT(off.mean, kTolerance) << c.rawlog;
    EXPECT_LT(off.covariance, kTolerance) << c.rawlog;
    std::cout << c.rawlog << ": readings used " << on.used << ", off start: gated " << off.gated
              << ", recoveries " << off.recoveries << "; largest differences " << on.mean << " / "
              << on.covariance << ", off start " << off.mean << " / " << off.covariance << "\n";
  }
  EXPECT_GT(recoveries, 0u);  // the recovery's solve too (MRCLAM)
  const auto ini = iniAt(kRoot + "/tests/data/EKF-SLAM_test_2d.ini");
  const auto steps = stepsOf(kRoot + "/rawlogs/kf-slam_demo.rawlog");
  const auto map = mapOf(*ini, steps);
  std::vector<Step> no_ids;
  for (const Step& s : steps) no_ids.push_back(withoutIds(s));
  const Gap paired = sideBySide(*ini, map, startAt(0, 0, 0), no_ids, kDefaultGate);
  EXPECT_GT(paired.used, 500u);
  EXPECT_LT(paired.mean, kTolerance);
  EXPECT_LT(paired.covariance, kTolerance);
}

// A simulated world's revisit relocalized in the map of its mapping route (the park, seed 1, as
// the benchmark's relocalization does it), from the revisit's true start in the map's frame.
TEST(SparseLocalization, EqualsMrptsIterationOnASimulatedRevisit) {
  dataset::SimulationOptions o;
  o.scenario = dataset::SimulationOptions::ScenarioKind::Park;
  o.seed = 1;
  const auto mapping = dataset::simulate(o);
  o.route = dataset::SimulationOptions::Route::Revisit;
  const auto revisit = dataset::simulate(o);

  mrpt::config::CConfigFileMemory ini;
  ini.write("RangeBearingKFSLAM", "std_sensor_range", mapping.noise.std_range);
  ini.write("RangeBearingKFSLAM", "std_sensor_yaw_deg", mapping.noise.std_yaw / kDeg);
  const auto map = mapOf(ini, mapping.steps);
  ASSERT_GT(map.size(), 100u);
  // The map's frame is the mapping's start pose.
  const mrpt::poses::CPose2D start =
      mrpt::poses::CPose2D(toTPose2D(revisit.ground_truth.path.front())) -
      mrpt::poses::CPose2D(toTPose2D(mapping.ground_truth.path.front()));
  const Gap gap =
      sideBySide(ini, map, startAt(start.x(), start.y(), start.phi()), revisit.steps, kDefaultGate);
  std::cout << "park revisit: " << gap.steps << " steps, " << map.size() << " landmarks, "
            << gap.used << " readings used, " << gap.gated << " gated; largest differences "
            << gap.mean << " / " << gap.covariance << "\n";
  EXPECT_GT(gap.used, gap.steps);
  EXPECT_LT(gap.mean, kTolerance);
  EXPECT_LT(gap.covariance, kTolerance);
}
