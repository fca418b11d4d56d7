#include "ConvertCommon.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"
#include "budget_slam/core/InputLimits.h"

namespace budget_slam::dataset::convert {

std::string baseName(const std::string& path) {
  std::string p = path;
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  const auto slash = p.find_last_of('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

Eigen::Matrix3d upperTriangle3(const TextTable& t, std::size_t first, const std::string& what) {
  Eigen::Matrix3d m;
  std::size_t k = first;
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      m(r, c) = m(c, r) =
          t.bounded(k++, what + "(" + std::to_string(r + 1) + "," + std::to_string(c + 1) + ")",
                    limits::kMaxVariance);
    }
  return m;
}

Eigen::Matrix2d upperTriangle2(const TextTable& t, std::size_t first, const std::string& what) {
  Eigen::Matrix2d m;
  std::size_t k = first;
  for (int r = 0; r < 2; ++r)
    for (int c = r; c < 2; ++c)
      m(r, c) = m(c, r) =
          t.bounded(k++, what + "(" + std::to_string(r + 1) + "," + std::to_string(c + 1) + ")",
                    limits::kMaxVariance);
  return m;
}

void checkCovariance(const TextTable& t, const Eigen::MatrixXd& m, const std::string& what,
                     bool strict) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m);
  const double scale = std::max(1.0, m.cwiseAbs().maxCoeff());
  const double lo = es.eigenvalues().minCoeff();
  if (strict ? !(lo > 0) : lo < -1e-12 * scale)
    t.fail(what + " is not positive " + (strict ? "definite" : "semi-definite"));
}

Eigen::MatrixXd covarianceOfInformation(const TextTable& t, const Eigen::MatrixXd& info) {
  const Eigen::MatrixXd cov = info.inverse();
  if (!cov.allFinite() || !(cov.cwiseAbs().maxCoeff() <= limits::kMaxVariance))
    t.fail(
        "information matrix is nearly singular (its inverse, the covariance, has an entry "
        "that is not finite or above 1e24)");
  return cov;
}

void checkSensorNoise(const SensorNoise& noise, const std::string& file) {
  const auto check = [&](double std, const char* what) {
    if (!(std >= IniSection::kMinStd && std <= IniSection::kMaxStd)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", std);
      throw InputError(file + ": the sensor noise it gives, " + what + " = " + value +
                       ", is not a standard deviation from 1e-12 to 1e12 (too few readings, or "
                       "all alike?)");
    }
  };
  check(noise.std_range, "std_range");
  check(noise.std_yaw, "std_yaw");
}

RangeBearingScan emptyScan(const SensorNoise& noise) {
  RangeBearingScan s;
  s.sensor_pose_on_robot = noise.sensor_pose_on_robot;
  s.min_range = noise.min_range;
  s.max_range = noise.max_range;
  s.fov_yaw = noise.fov_yaw;
  s.std_range = noise.std_range;
  s.std_yaw = noise.std_yaw;
  return s;
}

void limitsFromReadings(const std::vector<RangeBearingReading>& readings, SensorNoise& noise) {
  double max_range = 0, max_bearing = 0;
  for (const auto& r : readings) {
    max_range = std::max(max_range, r.range);
    max_bearing = std::max(max_bearing, std::abs(r.yaw));
  }
  noise.min_range = 0;
  noise.max_range = max_range;
  noise.fov_yaw = std::min(2 * M_PI, 2 * max_bearing);
}

}  // namespace budget_slam::dataset::convert
