#include <cmath>
#include <map>

#include "../TextTable.h"
#include "ConvertCommon.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/Converters.h"
#include "budget_slam/dataset/StepToMrpt.h"

namespace budget_slam::dataset {
namespace {

// Noise of the course's EKF-SLAM exercise framework (Freiburg "Robot Mapping"): motion noise
// R = diag(0.1, 0.1, 0.01) added per step (variances in m^2, m^2, rad^2; isotropic in x, y, so the
// same in the robot frame) and measurement noise Q = 0.01 I (range m^2, bearing rad^2).
constexpr double kMotionVarXY = 0.1;
constexpr double kMotionVarYaw = 0.01;
constexpr double kSensorVar = 0.01;

}  // namespace

ConvertedDataset convertFreiburg(const std::string& world, const std::string& sensor_data) {
  ConvertedDataset out;
  {
    TextTable t(world);
    std::map<LandmarkId, std::size_t> line_of;
    while (t.next()) {
      t.expectFields(3, "landmark (id x y)");
      const long long id = t.landmarkId(0, "landmark id");
      if (const auto it = line_of.find(id); it != line_of.end())
        t.fail("landmark id " + std::to_string(id) + " appears twice (first on line " +
               std::to_string(it->second) + ")");
      line_of[id] = t.line();
      out.ground_truth.landmarks[id] = Eigen::Vector2d(t.bounded(1, "x", limits::kMaxCoordinate),
                                                       t.bounded(2, "y", limits::kMaxCoordinate));
    }
  }
  out.noise.std_range = std::sqrt(kSensorVar);
  out.noise.std_yaw = std::sqrt(kSensorVar);

  // Pass 1: records; pass 2 (below) makes steps once the sensor limits are known.
  struct Block {
    std::optional<OdometryIncrement> odometry;
    std::vector<RangeBearingReading> readings;
    std::map<LandmarkId, std::size_t> line_of;
  };
  std::vector<Block> blocks;
  std::vector<RangeBearingReading> all;
  std::size_t negative_left_out = 0;
  TextTable t(sensor_data);
  while (t.next()) {
    const std::string& tag = t.word(0);
    if (tag == "ODOMETRY") {
      // Rotation r1, translation t, rotation r2 (the course's odometry motion model).
      t.expectFields(4, "ODOMETRY (r1 t r2)");
      const double r1 = t.bounded(1, "r1", limits::kMaxAngle),
                   tr = t.bounded(2, "t", limits::kMaxStepTranslation),
                   r2 = t.bounded(3, "r2", limits::kMaxAngle);
      if (blocks.size() >= limits::kMaxSteps)
        t.fail("more than " + std::to_string(limits::kMaxSteps) +
               " ODOMETRY records (steps of one conversion)");
      OdometryIncrement inc;
      inc.mean = {tr * std::cos(r1), tr * std::sin(r1), r1 + r2};
      inc.cov = Eigen::Vector3d(kMotionVarXY, kMotionVarXY, kMotionVarYaw).asDiagonal();
      blocks.push_back({inc, {}, {}});
    } else if (tag == "SENSOR") {
      t.expectFields(4, "SENSOR (id range bearing)");
      const long long id = t.landmarkId(1, "landmark id");
      const double range = t.bounded(2, "range", limits::kMaxRange),
                   bearing = t.bounded(3, "bearing", limits::kMaxAngle);
      if (range == 0) t.fail("SENSOR at zero range has no bearing");
      if (range < 0) {
        // Simulated noise on a landmark a few cm away; MRPT's filter cannot take it. Left out.
        ++negative_left_out;
        continue;
      }
      // Readings before the first ODOMETRY: a first step at the start pose, without motion.
      if (blocks.empty()) blocks.push_back({std::nullopt, {}, {}});
      auto& b = blocks.back();
      if (const auto it = b.line_of.find(id); it != b.line_of.end())
        t.fail("landmark " + std::to_string(id) + " seen twice in one step (first on line " +
               std::to_string(it->second) + ")");
      b.line_of[id] = t.line();
      b.readings.push_back({id, range, bearing, 0});
      all.push_back(b.readings.back());
    } else {
      t.fail("unknown record '" + tag + "' (expected ODOMETRY or SENSOR)");
    }
  }
  if (blocks.empty()) throw InputError(sensor_data + ": no ODOMETRY or SENSOR record");
  convert::limitsFromReadings(all, out.noise);
  for (const auto& b : blocks) {
    RangeBearingScan scan = convert::emptyScan(out.noise);
    scan.readings = b.readings;
    const StepIndex k = out.steps.size();
    out.steps.push_back(makeStep(k, static_cast<double>(k + 1), b.odometry, scan));
  }
  out.notes = {
      "Made by budget-convert --format freiburg from " + convert::baseName(world) + " and " +
          convert::baseName(sensor_data) + ".",
      "One step per ODOMETRY record (r1 t r2 -> dx = t cos r1, dy = t sin r1, dyaw = r1 + r2)",
      "with the SENSOR records after it. Times: step k at t = k + 1 s. Ids as in the files.",
      "Noise of the course's EKF-SLAM exercise: odometry covariance diag(0.1, 0.1, 0.01) per step,",
      "range and bearing variance 0.01. Ground truth: world.dat (the robot starts at the origin).",
      "SENSOR readings with a negative range left out: " + std::to_string(negative_left_out) + ".",
  };
  return out;
}

}  // namespace budget_slam::dataset
