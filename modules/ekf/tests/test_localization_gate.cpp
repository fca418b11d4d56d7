#include <gtest/gtest.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>
#include <random>

#include "budget_slam/dataset/Simulator.h"
#include "budget_slam/ekf/LocalizationKF2D.h"
#include "budget_slam/ekf/PoseFromPoints.h"

using namespace budget_slam;
using budget_slam::ekf::LocalizationKF2D;

namespace {

/// The rooms world's revisit route (seed 7), with `wrong` of the readings given the ID of another
/// landmark of the world (a wrong association: a reading that is not what it says it is), drawn
/// with a fixed seed. Returns the steps and the true path (row k + 1: the pose of step k).
dataset::ConvertedDataset withWrongReadings(double wrong, std::size_t* corrupted) {
  dataset::SimulationOptions o;
  o.scenario = dataset::SimulationOptions::ScenarioKind::Rooms;
  o.route = dataset::SimulationOptions::Route::Revisit;
  o.seed = 7;
  auto d = dataset::simulate(o);
  std::vector<LandmarkId> ids;
  for (const auto& [id, _] : d.ground_truth.landmarks) ids.push_back(id);
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0, 1);
  *corrupted = 0;
  for (Step& s : d.steps) {
    if (!s.scan || !s.frame) continue;
    auto frame = std::make_shared<mrpt::obs::CSensoryFrame>();
    for (const auto& obs : *s.frame) {
      auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(obs);
      if (!br) {
        frame->insert(obs);
        continue;
      }
      auto copy = std::make_shared<mrpt::obs::CObservationBearingRange>(*br);
      for (std::size_t i = 0; i < copy->sensedData.size(); ++i) {
        if (u(rng) >= wrong) continue;
        LandmarkId other;
        do other = ids[static_cast<std::size_t>(u(rng) * ids.size())];
        while (other == copy->sensedData[i].landmarkID);
        copy->sensedData[i].landmarkID = static_cast<int32_t>(other);
        s.scan->readings[i].id = other;
        ++*corrupted;
      }
      frame->insert(copy);
    }
    s.frame = frame;
  }
  return d;
}

/// The filter with `gate`, the sensor noise of `d`, its true landmarks (1 cm) as the map, started
/// at `start` (0.1 m, 0.03 rad).
void initialize(LocalizationKF2D& kf, const dataset::ConvertedDataset& d,
                const LocalizationKF2D::Gate& gate, const Pose2& start) {
  kf.KF_options.verbosity_level = mrpt::system::LVL_ERROR;
  kf.options.std_sensor_range = static_cast<float>(d.noise.std_range);
  kf.options.std_sensor_yaw = static_cast<float>(d.noise.std_yaw);
  kf.gate = gate;
  std::vector<LandmarkView> map;
  for (const auto& [id, p] : d.ground_truth.landmarks)
    map.push_back({id, p, Eigen::Matrix2d::Identity() * 1e-4});
  PoseEstimate s;
  s.mean = start;
  s.cov = Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal();
  kf.initialize(s, map);
}

/// Localizes the steps in the true map; returns the share of steps with a position error above
/// 1 m [%] and the largest error [m].
std::pair<double, double> localize(const dataset::ConvertedDataset& d,
                                   const LocalizationKF2D::Gate& gate) {
  LocalizationKF2D kf;
  initialize(kf, d, gate, d.ground_truth.path.front());
  std::size_t lost = 0;
  double worst = 0;
  for (std::size_t k = 0; k < d.steps.size(); ++k) {
    kf.processStep(d.steps[k]);
    const auto p = kf.robotPose().mean;
    const auto& t = d.ground_truth.path[k + 1];
    const double e =
        std::isfinite(p.x) && std::isfinite(p.y) ? std::hypot(p.x - t.x, p.y - t.y) : INFINITY;
    lost += !(e <= 1.0);
    worst = std::max(worst, e);
  }
  return {100.0 * static_cast<double>(lost) / static_cast<double>(d.steps.size()), worst};
}

}  // namespace

TEST(LocalizationGate, FivePercentWrongReadingsLoseTheRobotWithoutTheGateNotWithIt) {
  std::size_t corrupted = 0;
  const auto d = withWrongReadings(0.05, &corrupted);
  std::size_t readings = 0;
  for (const auto& s : d.steps) readings += s.scan ? s.scan->readings.size() : 0;
  ASSERT_GT(readings, 1000u);
  EXPECT_NEAR(static_cast<double>(corrupted) / static_cast<double>(readings), 0.05, 0.01);

  const auto [lost_gated, worst_gated] = localize(d, {13.8, 5, 20, 3});  // the defaults
  const auto [lost_open, worst_open] = localize(d, {0, 0, 0, 3});        // MRPT's filter as is
  std::cout << "5% wrong readings: gate lost " << lost_gated << "% (worst " << worst_gated
            << " m), no gate lost " << lost_open << "% (worst " << worst_open << " m)\n";
  EXPECT_EQ(lost_gated, 0.0);
  EXPECT_LT(worst_gated, 0.3);
  EXPECT_GT(lost_open, 10.0);
}

TEST(LocalizationGate, RecoversFromAWrongStartThatTheGateAloneNeverLeaves) {
  // The robot starts 3 m and 40 deg away from where the filter believes it is, with a confident
  // start: the gate rejects every reading, so without recovery the filter dead-reckons for good;
  // with it, the pose is solved afresh from the rejected readings and tracked from then on.
  dataset::SimulationOptions o;
  o.scenario = dataset::SimulationOptions::ScenarioKind::Rooms;
  o.route = dataset::SimulationOptions::Route::Revisit;
  o.seed = 3;
  auto d = dataset::simulate(o);
  const auto run = [&](const LocalizationKF2D::Gate& gate) {
    LocalizationKF2D kf;
    Pose2 start = d.ground_truth.path.front();
    start.x += 3;
    start.phi += 40 * M_PI / 180;
    initialize(kf, d, gate, start);
    std::size_t recovered_at = 0, tracked_after = 0, steps_after = 0;
    for (std::size_t k = 0; k < d.steps.size(); ++k) {
      kf.processStep(d.steps[k]);
      if (kf.lastRecovered() && !recovered_at) recovered_at = k;
      const auto p = kf.robotPose().mean;
      const auto& t = d.ground_truth.path[k + 1];
      if (k >= 50) ++steps_after, tracked_after += std::hypot(p.x - t.x, p.y - t.y) < 0.25;
    }
    return std::pair{recovered_at, 100.0 * tracked_after / static_cast<double>(steps_after)};
  };
  const auto [never, tracked_without] = run({13.8, 0, 20, 3});
  const auto [at, tracked_with] = run({13.8, 5, 20, 3});
  EXPECT_EQ(never, 0u);
  EXPECT_LT(tracked_without, 5.0);
  EXPECT_GT(at, 0u);
  EXPECT_LT(at, 50u);
  EXPECT_GT(tracked_with, 95.0);
}

TEST(PoseFromPoints, FitsThePoseOfPointsSeenFromIt) {
  // Three landmarks seen from (2, -1, 0.6): the fit returns that pose; with one landmark (or one
  // point twice) there is no 2D pose to fit.
  const Pose2 truth(2, -1, 0.6);
  const double c = std::cos(truth.phi), s = std::sin(truth.phi);
  std::vector<ekf::PointMatch> m;
  for (const Eigen::Vector2d q :
       {Eigen::Vector2d(3, 1), Eigen::Vector2d(1, -2), Eigen::Vector2d(4, 0.5)}) {
    ekf::PointMatch p;
    p.in_robot = q;
    p.in_map = Eigen::Vector2d(truth.x + c * q.x() - s * q.y(), truth.y + s * q.x() + c * q.y());
    p.cov_in_robot = p.cov_in_map = Eigen::Matrix2d::Identity() * 1e-4;
    m.push_back(p);
  }
  const auto fit = ekf::fitPose(m);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->pose.mean.x, 2, 1e-9);
  EXPECT_NEAR(fit->pose.mean.y, -1, 1e-9);
  EXPECT_NEAR(fit->pose.mean.phi, 0.6, 1e-9);
  EXPECT_LT(fit->worst_d2, 1e-12);
  EXPECT_GT(fit->pose.cov(0, 0), 0);
  EXPECT_FALSE(ekf::fitPose({m[0]}));
  EXPECT_FALSE(ekf::fitPose({m[0], m[0]}));
  // A point moved by 0.5 m no longer agrees with the others (sigma 1 cm).
  m[2].in_map.x() += 0.5;
  EXPECT_GT(ekf::fitPose(m)->worst_d2, 13.8);
}
