#include "budget_slam/dataset/Simulator.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "Random.h"
#include "Scenario.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/MrptPose.h"
#include "budget_slam/dataset/DatasetFiles.h"
#include "budget_slam/dataset/RawlogWriter.h"
#include "budget_slam/dataset/Sessions.h"
#include "budget_slam/dataset/SidecarIni.h"
#include "budget_slam/dataset/StepToMrpt.h"

namespace budget_slam::dataset {
namespace {

using mrpt::poses::CPose2D;
constexpr double kDeg = M_PI / 180;
/// Smallest standard deviation a rawlog states (m, rad): with zero noise the stated covariance
/// stays invertible for the graph backend, and 1e-6 is far below any real sensor.
constexpr double kMinStd = 1e-6;
/// Smallest standard deviation the sidecar states for a reading (m, rad): budget-slam refuses 0,
/// and its EKF loses positive definiteness with a range noise of 1e-6 m on the rooms scenario
/// while 1e-5 m runs; 1e-4 (0.1 mm, 0.006 deg) is still far below any real sensor.
constexpr double kMinReadingStd = 1e-4;

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

/// A noise option: < 0 (the scenario's default), or a standard deviation in [0, most]. The most
/// keeps every reading, step and sidecar value within what budget-slam reads
/// (core/InputLimits.h, IniSection::readStd): a draw beyond ten standard deviations (odds below
/// 1e-22) is never made. ConfigError names the budget-simulate flag.
void checkNoise(const char* flag, double v, double most, const char* unit) {
  if (std::isnan(v) || v > most)
    throw ConfigError(std::string("--") + flag + " " + num(v) + ": must be at most " + num(most) +
                      " " + unit + " (ten standard deviations within what budget-slam reads)");
}

}  // namespace

struct Simulator::Impl {
  SimulationOptions options;
  sim::Scenario scenario;
  EpochSchedule epochs;
  SensorNoise noise;
  double odo_std_xy = 0, odo_std_yaw = 0;
  GroundTruth gt;
  std::size_t steps = 0, readings = 0;
  double length = 0;
};

Simulator::Simulator(const SimulationOptions& options)
    : Simulator(options,
                sim::makeScenario(options.scenario, options.seed, options.laps, options.route),
                EpochSchedule()) {}

Simulator::Simulator(const SimulationOptions& options, const sim::Scenario& scenario,
                     const EpochSchedule& epochs)
    : impl_(std::make_unique<Impl>()) {
  auto& m = *impl_;
  m.options = options;
  if (!(options.dt > 0)) throw ConfigError("dt must be positive");
  m.scenario = scenario;
  m.epochs = epochs;
  checkNoise("odo-std-xy", options.odo_std_xy, limits::kMaxStepTranslation / 10, "m");
  checkNoise("odo-std-yaw-deg", options.odo_std_yaw_deg, limits::kMaxAngle / 10 / kDeg, "deg");
  checkNoise("sensor-std-range", options.sensor_std_range, limits::kMaxRange / 10, "m");
  // The bearing is wrapped; the reducers read std_sensor_yaw_deg up to a full turn.
  checkNoise("sensor-std-yaw-deg", options.sensor_std_yaw_deg, 360, "deg");
  m.noise = m.scenario.sensor;
  if (options.sensor_std_range >= 0) m.noise.std_range = options.sensor_std_range;
  if (options.sensor_std_yaw_deg >= 0) m.noise.std_yaw = options.sensor_std_yaw_deg * kDeg;
  m.odo_std_xy = options.odo_std_xy >= 0 ? options.odo_std_xy : m.scenario.odo_std_xy;
  m.odo_std_yaw =
      options.odo_std_yaw_deg >= 0 ? options.odo_std_yaw_deg * kDeg : m.scenario.odo_std_yaw;
  // A session of a changing world: the landmarks of its epoch; else every landmark that ever is.
  for (const auto& l : m.scenario.world.landmarks)
    if (epochs.fixed < 0 || (l.first_lap <= epochs.fixed && epochs.fixed <= l.last_lap))
      m.gt.landmarks[l.id] = l.p;
}

Simulator::~Simulator() = default;

const GroundTruth& Simulator::groundTruth() const { return impl_->gt; }
SensorNoise Simulator::noise() const {
  // A reading's standard deviation below kMinReadingStd (zero noise included) is stated as
  // kMinReadingStd, so that the sidecar holds a value budget-slam reads and filters with.
  SensorNoise stated = impl_->noise;
  stated.std_range = std::max(stated.std_range, kMinReadingStd);
  stated.std_yaw = std::max(stated.std_yaw, kMinReadingStd);
  return stated;
}

void Simulator::run(const std::function<void(const Step&)>& sink) {
  auto& m = *impl_;
  const auto& sc = m.scenario;
  const auto& world = sc.world;
  // Its own stream for the noise, so that the world does not depend on the noise settings; the
  // revisit route has another one (the same world, other noise).
  const std::uint64_t stream = m.epochs.noise_stream
                                   ? m.epochs.noise_stream
                                   : (m.options.route == SimulationOptions::Route::Revisit ? 2 : 1);
  sim::Random rng(m.options.seed * 0x9E3779B97F4A7C15ULL + stream);
  const CPose2D sensor_on_robot(m.noise.sensor_pose_on_robot.x, m.noise.sensor_pose_on_robot.y,
                                m.noise.sensor_pose_on_robot.yaw);
  CPose2D pose(sc.start.x(), sc.start.y(), sc.start_yaw);
  m.gt.path.assign(1, toPose2(pose.asTPose()));
  m.steps = m.readings = 0;
  m.length = 0;
  int lap = 0;

  OdometryIncrement odo;
  odo.cov = Eigen::Vector3d(std::pow(std::max(m.odo_std_xy, kMinStd), 2),
                            std::pow(std::max(m.odo_std_xy, kMinStd), 2),
                            std::pow(std::max(m.odo_std_yaw, kMinStd), 2))
                .asDiagonal();
  const bool all_around = m.noise.fov_yaw >= 2 * M_PI - 1e-9;

  auto emit = [&](const CPose2D& inc) {
    pose = pose + inc;  // the true pose is the composition of the true increments
    m.length += std::hypot(inc.x(), inc.y());
    // A robot standing still reads no motion (as in MRPT's simul-landmarks).
    const bool still = inc.x() == 0 && inc.y() == 0 && inc.phi() == 0;
    odo.mean = toPose2(still ? mrpt::math::TPose2D(0, 0, 0)
                             : mrpt::math::TPose2D(inc.x() + rng.normal(m.odo_std_xy),
                                                   inc.y() + rng.normal(m.odo_std_xy),
                                                   inc.phi() + rng.normal(m.odo_std_yaw)));
    RangeBearingScan scan;
    scan.sensor_pose_on_robot = m.noise.sensor_pose_on_robot;
    scan.min_range = m.noise.min_range;
    scan.max_range = m.noise.max_range;
    scan.fov_yaw = m.noise.fov_yaw;
    scan.std_range = m.noise.std_range;
    scan.std_yaw = m.noise.std_yaw;
    const CPose2D s = pose + sensor_on_robot;
    const Eigen::Vector2d sp(s.x(), s.y());
    const int region =
        world.regions.empty() ? -1 : world.regionOf(Eigen::Vector2d(pose.x(), pose.y()));
    for (const auto i : world.near(sp, m.noise.max_range)) {
      const auto& l = world.landmarks[i];
      const int epoch = m.epochs.epochOf(lap);
      if (epoch < l.first_lap || epoch > l.last_lap) continue;
      if (l.region >= 0 && l.region != region) continue;
      const Eigen::Vector2d d = l.p - sp;
      const double range = d.norm();
      if (range < m.noise.min_range || range <= 0) continue;
      const double bearing = mrpt::math::wrapToPi(std::atan2(d.y(), d.x()) - s.phi());
      if (!all_around && std::abs(bearing) > m.noise.fov_yaw / 2) continue;
      if (world.occluded(sp, l.p)) continue;
      const double r = range + rng.normal(m.noise.std_range);
      const double b = mrpt::math::wrapToPi(bearing + rng.normal(m.noise.std_yaw));
      if (r <= 0) continue;
      scan.readings.push_back({m.options.with_ids ? l.id : kNoLandmarkId, r, b, 0});
    }
    m.readings += scan.readings.size();
    const StepIndex k = m.steps++;
    sink(makeStep(k, static_cast<double>(k + 1) * m.options.dt, odo, scan));
    m.gt.path.push_back(toPose2(pose.asTPose()));
  };

  // Step 0 stands still at the start pose: MRPT's 2D EKF does not predict while its map is
  // empty, so its frame is the pose of the first step with a reading; observing from the start
  // pose first makes that frame the ground truth's.
  emit(CPose2D(0, 0, 0));
  for (lap = 0; lap < sc.laps; ++lap)
    for (const auto& wp : sc.route) {
      for (std::size_t guard = 0;; ++guard) {
        if (guard > 1000000) throw std::logic_error("simulator: waypoint never reached");
        const Eigen::Vector2d d = wp - Eigen::Vector2d(pose.x(), pose.y());
        const double dist = d.norm();
        if (dist < sc.step / 2) break;
        const double err = mrpt::math::wrapToPi(std::atan2(d.y(), d.x()) - pose.phi());
        const double turn = std::clamp(err, -sc.max_turn, sc.max_turn);
        // Turn, then drive along the new heading; turn in place while far off course.
        const double fwd = std::abs(err) <= 45 * kDeg ? std::min(sc.step, dist) : 0.0;
        emit(CPose2D(fwd * std::cos(turn), fwd * std::sin(turn), turn));
      }
    }
}

std::vector<std::string> Simulator::notes() const {
  const auto& m = *impl_;
  const auto& o = m.options;
  std::vector<std::string> n = {
      "Made by budget-simulate --scenario " + o.scenarioName() + " --seed " +
          std::to_string(o.seed) + (o.with_ids ? "" : " --no-ids") +
          (o.route == SimulationOptions::Route::Default ? "" : " --route " + o.routeName()) +
          (o.laps > 0 ? " --laps " + std::to_string(o.laps) : "") + ".",
      m.scenario.description,
      "Odometry: true increment + Gaussian noise, std " + num(m.odo_std_xy) + " m (x, y) and " +
          num(m.odo_std_yaw / kDeg) + " deg (yaw) per step; stated covariance the same (at least " +
          "1e-6 std).",
      "Readings: landmarks in range and field of view not hidden by a wall" +
          std::string(m.scenario.world.regions.empty() ? "" : " and in the robot's room") +
          "; Gaussian range and bearing noise with the stds below.",
      "Step 0 stands still at the start pose (zero motion). Times: step k at t = (k + 1) x " +
          num(o.dt) + " s. Ground truth: start pose, then one pose a step.",
  };
  if (o.route == SimulationOptions::Route::Revisit)
    n.push_back(
        "Revisit route: the world, landmark ids and frame of --route default (whose start pose "
        "is "
        "the origin); this path starts at (" +
        num(m.scenario.start.x()) + ", " + num(m.scenario.start.y()) + ") m, yaw " +
        num(m.scenario.start_yaw / kDeg) + " deg, with another noise stream.");
  if (m.steps)
    n.push_back(std::to_string(m.steps) + " steps, " + std::to_string(m.readings) + " readings, " +
                std::to_string(m.gt.landmarks.size()) + " landmarks, path " + num(m.length) +
                " m.");
  return n;
}

ConvertedDataset simulate(const SimulationOptions& options) {
  Simulator sim(options);
  ConvertedDataset out;
  sim.run([&](const Step& s) { out.steps.push_back(s); });
  out.ground_truth = sim.groundTruth();
  out.noise = sim.noise();
  out.notes = sim.notes();
  return out;
}

std::size_t simulateToFiles(const SimulationOptions& options, const std::string& rawlog,
                            bool force) {
  checkRawlogName(rawlog);
  Simulator sim(options);
  RawlogWriter writer(rawlog);
  sim.run([&](const Step& s) {
    Cancellation::check();
    writer.write(s);
  });
  saveDatasetFiles(writer, sim.groundTruth(), sim.noise(), sim.notes(), force);
  return writer.stepsWritten();
}

}  // namespace budget_slam::dataset
